// OpenSubdiv 3.x peer harness for lsubdiv (see README.md beside this file).
//
//   osd_bench --obj MESH.obj --name NAME --levels L [--runs R] [--dump OUT.bin]
//
// Builds a Far::TopologyRefiner from the OBJ's quads (Far::TopologyDescriptor, Catmull-Clark,
// boundaries edge-and-corner as lsubdiv's default), refines it uniformly L levels, allocates
// the primvar buffer for all levels once, and times only Far::PrimvarRefiner::Interpolate of
// levels 1..L on double-precision positions: one warm-up, then the median of R runs (R >= 7).
// Prints `RESULT impl=opensubdiv-c++ ...` like the Rust harnesses. With --dump, writes the final
// level's positions and faces in the shared dump format (magic LSPEERS1, u64 nv, u64 nf,
// nv*3 f64, nf*4 u32, little-endian) for the accuracy check.

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

// A position in double precision with the interface PrimvarRefiner expects.
struct Vertex {
    double x, y, z;
    void Clear(void * = 0) { x = y = z = 0.0; }
    void AddWithWeight(Vertex const &src, float weight) {
        double w = weight;
        x += w * src.x;
        y += w * src.y;
        z += w * src.z;
    }
};

struct Obj {
    std::vector<Vertex> positions;
    std::vector<int> faceVerts;  // 4 per face, 0-based
    std::vector<int> creasePairs;  // from `t crease 2/1/0 a b s` (0-based, OpenSubdiv's shapes)
    std::vector<float> creaseWeights;
};

bool readObj(const std::string &path, Obj &obj, std::string &err) {
    std::ifstream in(path);
    if (!in) {
        err = path + ": cannot open";
        return false;
    }
    std::string line;
    int lineNo = 0;
    while (std::getline(in, line)) {
        ++lineNo;
        std::istringstream s(line);
        std::string tag;
        if (!(s >> tag)) continue;
        if (tag == "v") {
            Vertex v;
            if (!(s >> v.x >> v.y >> v.z)) {
                err = path + ":" + std::to_string(lineNo) + ": bad vertex";
                return false;
            }
            obj.positions.push_back(v);
        } else if (tag == "f") {
            std::string tok;
            int n = 0;
            while (s >> tok) {
                obj.faceVerts.push_back(std::atoi(tok.c_str()) - 1);  // "i", "i/t", "i//n"
                ++n;
            }
            if (n != 4) {
                err = path + ":" + std::to_string(lineNo) + ": face is not a quad";
                return false;
            }
        } else if (tag == "t") {
            std::string name, counts;
            int a, b;
            float w;
            if (!(s >> name) || name != "crease") continue;
            if (!(s >> counts >> a >> b >> w) || counts.compare(0, 3, "2/1") != 0) {
                err = path + ":" + std::to_string(lineNo) + ": only `t crease 2/1/0 a b s` is read";
                return false;
            }
            obj.creasePairs.push_back(a);
            obj.creasePairs.push_back(b);
            obj.creaseWeights.push_back(w);
        }
    }
    return true;
}

bool writeDump(const std::string &path, const Vertex *pos, size_t nv,
               const std::vector<uint32_t> &faces) {
    FILE *f = std::fopen(path.c_str(), "wb");
    if (!f) return false;
    uint64_t header[2] = {nv, faces.size() / 4};
    bool ok = std::fwrite("LSPEERS1", 1, 8, f) == 8 &&
              std::fwrite(header, sizeof(uint64_t), 2, f) == 2;
    for (size_t i = 0; ok && i < nv; ++i) {
        double p[3] = {pos[i].x, pos[i].y, pos[i].z};
        ok = std::fwrite(p, sizeof(double), 3, f) == 3;
    }
    if (ok && !faces.empty())
        ok = std::fwrite(faces.data(), sizeof(uint32_t), faces.size(), f) == faces.size();
    return std::fclose(f) == 0 && ok;
}

const char *arg(int argc, char **argv, const char *key, const char *def) {
    for (int i = 1; i + 1 < argc; ++i)
        if (std::strcmp(argv[i], key) == 0) return argv[i + 1];
    return def;
}

}  // namespace

int main(int argc, char **argv) {
    const char *objPath = arg(argc, argv, "--obj", nullptr);
    if (!objPath) {
        std::fprintf(stderr, "usage: osd_bench --obj M.obj --name N --levels L [--runs R] [--dump F]\n");
        return 2;
    }
    std::string name = arg(argc, argv, "--name", objPath);
    int levels = std::atoi(arg(argc, argv, "--levels", "3"));
    int runs = std::max(1, std::atoi(arg(argc, argv, "--runs", "7")));
    const char *dump = arg(argc, argv, "--dump", nullptr);

    Obj obj;
    std::string err;
    if (!readObj(objPath, obj, err)) {
        std::fprintf(stderr, "error: %s\n", err.c_str());
        return 1;
    }

    typedef Far::TopologyDescriptor Descriptor;
    Sdc::Options options;
    // lsubdiv's default boundary rule (the open grid; unused on closed meshes).
    options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);

    int nFaces = (int)(obj.faceVerts.size() / 4);
    std::vector<int> vertsPerFace(nFaces, 4);
    Descriptor desc;
    desc.numVertices = (int)obj.positions.size();
    desc.numFaces = nFaces;
    desc.numVertsPerFace = vertsPerFace.data();
    desc.vertIndicesPerFace = obj.faceVerts.data();
    desc.numCreases = (int)obj.creaseWeights.size();
    desc.creaseVertexIndexPairs = obj.creasePairs.data();
    desc.creaseWeights = obj.creaseWeights.data();

    auto t0 = std::chrono::steady_clock::now();
    Far::TopologyRefiner *refiner = Far::TopologyRefinerFactory<Descriptor>::Create(
        desc, Far::TopologyRefinerFactory<Descriptor>::Options(Sdc::SCHEME_CATMARK, options));
    if (!refiner) {
        std::fprintf(stderr, "error: TopologyRefinerFactory::Create failed\n");
        return 1;
    }
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    // One buffer for all levels, allocated (and touched) once.
    std::vector<Vertex> buffer(refiner->GetNumVerticesTotal());
    std::copy(obj.positions.begin(), obj.positions.end(), buffer.begin());
    std::vector<Vertex *> levelStart(levels + 1);
    {
        Vertex *p = buffer.data();
        for (int l = 0; l <= levels; ++l) {
            levelStart[l] = p;
            p += refiner->GetLevel(l).GetNumVertices();
        }
    }
    Far::PrimvarRefiner primvar(*refiner);
    auto interpolateAll = [&]() {
        for (int l = 1; l <= levels; ++l) {
            Vertex *src = levelStart[l - 1];
            Vertex *dst = levelStart[l];
            primvar.Interpolate(l, src, dst);
        }
    };

    interpolateAll();  // warm-up
    std::vector<double> times;
    for (int r = 0; r < runs; ++r) {
        auto t = std::chrono::steady_clock::now();
        interpolateAll();
        times.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
        // Keep the result observable so the work cannot be elided.
        volatile double sink = levelStart[levels][r % 7].x;
        (void)sink;
    }
    std::sort(times.begin(), times.end());
    double med = times[times.size() / 2];

    Far::TopologyLevel const &last = refiner->GetLevel(levels);
    size_t outVerts = (size_t)last.GetNumVertices();
    std::printf(
        "RESULT impl=opensubdiv-c++ mesh=%s levels=%d out_vertices=%zu median_s=%.6f "
        "mvps=%.3f setup_s=%.3f\n",
        name.c_str(), levels, outVerts, med, outVerts / med / 1e6, setup);

    if (dump) {
        std::vector<uint32_t> faces;
        faces.reserve((size_t)last.GetNumFaces() * 4);
        for (int f = 0; f < last.GetNumFaces(); ++f) {
            Far::ConstIndexArray fv = last.GetFaceVertices(f);
            for (int k = 0; k < fv.size(); ++k) faces.push_back((uint32_t)fv[k]);
        }
        if (!writeDump(dump, levelStart[levels], outVerts, faces)) {
            std::fprintf(stderr, "error: cannot write %s\n", dump);
            return 1;
        }
    }
    delete refiner;
    return 0;
}
