// OpenSubdiv 3.x reference driver for tests/opensubdiv_shapes.rs: uniform Catmark refinement
// of an OBJ shape with the options OpenSubdiv's regression drivers give it.
//
//   osd_refine MESH.obj LEVELS BOUNDARY CREASE TRI [FVAR] > OUT
//
// BOUNDARY: none | edge-only | edge-and-corner; CREASE: uniform | chaikin; TRI: catmark | smooth;
// FVAR: none | corners-only | corners-plus1 | corners-plus2 | boundaries | all (Sdc::Options).
// With FVAR the texture coordinates (`vt`, corners `i/t`) are a face-varying channel refined
// with the mesh (Far::PrimvarRefinerReal::InterpolateFaceVarying), written `vt u v t` and
// faces `f a/t …`. Reads `v` and `f` lines (any polygon, `i/t/n` corners, negative indices) and
// the tags `t crease`, `t corner`, `t hole` (OpenSubdiv's shape files, vertices counted from 0),
// builds Far::TopologyRefinerFactory<Far::TopologyDescriptor>, refines uniformly LEVELS levels
// and interpolates positions in double (Far::PrimvarRefinerReal<double>). Writes the last level:
// `v x y z t` per vertex, t the vertex's taint (below), then `f a b c d` per face (0-based).
//
// Texture values are tainted too where OpenSubdiv 3.5 counts a vertex's values wrongly: its
// Vtr::FVarLevel::completeTopologyFromFaceValues compares a new value with the first of two
// found only, so around a vertex whose faces' values run A, B, A, B it makes the second B
// another value (a smooth crease of one face) where it means one value on disjoint faces (a
// corner). The children of such a vertex's values, and what depends on them, are tainted.
//
// Taint marks what lsubdiv's L-system rule may change (a texture value: the values of a tainted
// vertex's child where its face-varying topology matches the mesh's, and what depends on them): at each level taken by the scheme (every
// level of an all-quad base, every level after the first otherwise: the first step of a mesh
// with other polygons is Catmull-Clark's in lsubdiv too), the child of a vertex whose rule is
// smooth or dart, or blends into smooth or dart across the step (a rule transition of weight
// below 1), and whose valence is neither 4 nor 2 ([G] §3's extraordinary-vertex rule, not
// Catmull-Clark's; at valence 2 lsubdiv takes Catmull-Clark's weights) is tainted 1, and every vertex's taint is carried to the next level by the
// absolute values of its weights: taint 0 means the vertex depends on no such child.

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

namespace {

// Whether OpenSubdiv's count of the distinct values around a vertex (the loop of
// completeTopologyFromFaceValues, its faces' values in order) is not the true count.
bool miscounted(std::vector<int> const &values) {
    std::vector<int> unique{values[0]};
    for (std::size_t i = 1; i < values.size(); ++i) {
        if (values[i] == values[i - 1]) continue;
        if (unique.size() == 1 || (unique.size() == 2 && unique[0] != values[i])) {
            unique.push_back(values[i]);
        } else if (std::find(unique.begin(), unique.end(), values[i]) == unique.end()) {
            unique.push_back(values[i]);
        }
    }
    std::vector<int> sorted = values;
    std::sort(sorted.begin(), sorted.end());
    return unique.size() != (std::size_t)(std::unique(sorted.begin(), sorted.end()) - sorted.begin());
}

struct Point {
    double x, y, z, taint;
    void Clear(void * = 0) { x = y = z = taint = 0.0; }
    void AddWithWeight(Point const &src, double w) {
        x += w * src.x;
        y += w * src.y;
        z += w * src.z;
        taint += std::fabs(w) * src.taint;
    }
};

struct Shape {
    std::vector<Point> points, uvs;
    std::vector<int> counts, corners, uvCorners;
    std::vector<int> creasePairs, cornerVerts, holes;
    std::vector<float> creaseWeights, cornerWeights;
};

[[noreturn]] void fail(const std::string &what) {
    std::fprintf(stderr, "osd_refine: %s\n", what.c_str());
    std::exit(2);
}

Shape read(const char *path) {
    std::ifstream in(path);
    if (!in) fail(std::string(path) + ": cannot open");
    Shape s;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream l(line);
        std::string tag;
        if (!(l >> tag)) continue;
        if (tag == "v") {
            Point p{0, 0, 0, 0};
            l >> p.x >> p.y >> p.z;
            s.points.push_back(p);
        } else if (tag == "vt") {
            Point p{0, 0, 0, 0};
            l >> p.x >> p.y;
            s.uvs.push_back(p);
        } else if (tag == "f") {
            std::string tok;
            int n = 0;
            while (l >> tok) {
                int i = std::atoi(tok.c_str());
                s.corners.push_back(i < 0 ? (int)s.points.size() + i : i - 1);
                std::size_t slash = tok.find('/');
                int t = slash == std::string::npos ? 0 : std::atoi(tok.c_str() + slash + 1);
                s.uvCorners.push_back(t < 0 ? (int)s.uvs.size() + t : t - 1);
                ++n;
            }
            s.counts.push_back(n);
        } else if (tag == "t") {
            std::string name, count;
            l >> name >> count;
            int ni = 0, nf = 0;
            std::sscanf(count.c_str(), "%d/%d", &ni, &nf);
            std::vector<int> ints(ni);
            std::vector<float> floats(nf);
            for (int &i : ints) l >> i;
            for (float &f : floats) {
                std::string tok;
                l >> tok;
                f = tok == "inf" ? 10.0f : std::strtof(tok.c_str(), nullptr);
            }
            if (name == "crease") {
                for (int k = 0; k + 1 < ni; k += 2) {
                    s.creasePairs.push_back(ints[k]);
                    s.creasePairs.push_back(ints[k + 1]);
                    s.creaseWeights.push_back(floats[nf > 1 ? k / 2 : 0]);
                }
            } else if (name == "corner") {
                for (int k = 0; k < ni; ++k) {
                    s.cornerVerts.push_back(ints[k]);
                    s.cornerWeights.push_back(floats[nf > 1 ? k : 0]);
                }
            } else if (name == "hole") {
                s.holes.insert(s.holes.end(), ints.begin(), ints.end());
            }
        }
    }
    return s;
}

}  // namespace

int main(int argc, char **argv) {
    if (argc != 6 && argc != 7) fail("usage: osd_refine MESH.obj LEVELS BOUNDARY CREASE TRI [FVAR]");
    Shape s = read(argv[1]);
    int levels = std::atoi(argv[2]);
    std::string boundary = argv[3], crease = argv[4], tri = argv[5];
    std::string fvar = argc == 7 ? argv[6] : "";
    if (!fvar.empty()) {
        for (int t : s.uvCorners) {
            if (t < 0 || t >= (int)s.uvs.size()) fail(std::string(argv[1]) + ": a corner without texture coordinates");
        }
    }

    Sdc::Options options;
    options.SetVtxBoundaryInterpolation(
        boundary == "none"        ? Sdc::Options::VTX_BOUNDARY_NONE
        : boundary == "edge-only" ? Sdc::Options::VTX_BOUNDARY_EDGE_ONLY
                                  : Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
    options.SetCreasingMethod(crease == "chaikin" ? Sdc::Options::CREASE_CHAIKIN
                                                  : Sdc::Options::CREASE_UNIFORM);
    options.SetTriangleSubdivision(tri == "smooth" ? Sdc::Options::TRI_SUB_SMOOTH
                                                   : Sdc::Options::TRI_SUB_CATMARK);
    options.SetFVarLinearInterpolation(
        fvar == "none"            ? Sdc::Options::FVAR_LINEAR_NONE
        : fvar == "corners-only"  ? Sdc::Options::FVAR_LINEAR_CORNERS_ONLY
        : fvar == "corners-plus1" ? Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1
        : fvar == "corners-plus2" ? Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2
        : fvar == "boundaries"    ? Sdc::Options::FVAR_LINEAR_BOUNDARIES
                                  : Sdc::Options::FVAR_LINEAR_ALL);

    Far::TopologyDescriptor desc;
    desc.numVertices = (int)s.points.size();
    desc.numFaces = (int)s.counts.size();
    desc.numVertsPerFace = s.counts.data();
    desc.vertIndicesPerFace = s.corners.data();
    desc.numCreases = (int)s.creaseWeights.size();
    desc.creaseVertexIndexPairs = s.creasePairs.data();
    desc.creaseWeights = s.creaseWeights.data();
    desc.numCorners = (int)s.cornerWeights.size();
    desc.cornerVertexIndices = s.cornerVerts.data();
    desc.cornerWeights = s.cornerWeights.data();
    desc.numHoles = (int)s.holes.size();
    desc.holeIndices = s.holes.data();
    Far::TopologyDescriptor::FVarChannel channel;
    if (!fvar.empty()) {
        channel.numValues = (int)s.uvs.size();
        channel.valueIndices = s.uvCorners.data();
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }

    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    Far::TopologyRefiner *refiner =
        Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, options));
    if (!refiner) fail(std::string(argv[1]) + ": Far refused the topology");
    refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));

    bool quads = true;
    for (int n : s.counts) quads = quads && n == 4;

    std::vector<Point> level = s.points, uvs = s.uvs;
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    for (int l = 1; l <= levels; ++l) {
        Far::TopologyLevel const &parent = refiner->GetLevel(l - 1);
        std::vector<Point> next(refiner->GetLevel(l).GetNumVertices());
        primvar.Interpolate(l, level, next);
        std::vector<Point> nextUvs;
        if (!fvar.empty()) {
            nextUvs.resize(refiner->GetLevel(l).GetNumFVarValues(0));
            primvar.InterpolateFaceVarying(l, uvs, nextUvs, 0);
            Far::TopologyLevel const &children = refiner->GetLevel(l);
            for (int v = 0; l == 1 && v < parent.GetNumVertices(); ++v) {
                Far::ConstIndexArray faces = parent.GetVertexFaces(v);
                Far::ConstLocalIndexArray in = parent.GetVertexFaceLocalIndices(v);
                std::vector<int> values;
                for (int i = 0; i < faces.size(); ++i) {
                    values.push_back(parent.GetFaceFVarValues(faces[i], 0)[in[i]]);
                }
                int child = parent.GetVertexChildVertex(v);
                if (values.empty() || child < 0 || !miscounted(values)) continue;
                Far::ConstIndexArray cFaces = children.GetVertexFaces(child);
                Far::ConstLocalIndexArray cIn = children.GetVertexFaceLocalIndices(child);
                for (int i = 0; i < cFaces.size(); ++i) {
                    nextUvs[children.GetFaceFVarValues(cFaces[i], 0)[cIn[i]]].taint = 1.0;
                }
            }
        }
        if (quads || l > 1) {
            Far::TopologyLevel const &children = refiner->GetLevel(l);
            auto smooth = [](Sdc::Crease::Rule r) {
                return r == Sdc::Crease::RULE_SMOOTH || r == Sdc::Crease::RULE_DART;
            };
            for (int v = 0; v < parent.GetNumVertices(); ++v) {
                int child = parent.GetVertexChildVertex(v);
                // Valence 4 is the regular rule; at valence 2 lsubdiv's alpha is
                // Catmull-Clark's (EvCoefficients::alpha): neither is tainted.
                int valence = parent.GetVertexFaces(v).size();
                if (child < 0 || valence == 4 || valence == 2) continue;
                Sdc::Crease::Rule rule = parent.GetVertexRule(v);
                Sdc::Crease::Rule next_rule = children.GetVertexRule(child);
                // The smooth rule, alone or in a rule transition of weight below 1
                // (Sdc::Crease::ComputeFractionalWeightAtVertex, uniform creasing).
                bool blends = false;
                if (!smooth(rule) && smooth(next_rule)) {
                    float sum = 0.0f;
                    int count = 0;
                    float pv = parent.GetVertexSharpness(v);
                    if (pv > 0.0f && children.GetVertexSharpness(child) <= 0.0f) {
                        sum = pv;
                        count = 1;
                    }
                    Far::ConstIndexArray edges = parent.GetVertexEdges(v);
                    for (int i = 0; i < edges.size(); ++i) {
                        float s = parent.GetEdgeSharpness(edges[i]);
                        if (s > 0.0f && s <= 1.0f) {
                            sum += s;
                            ++count;
                        }
                    }
                    blends = count == 0 || sum / count < 1.0f;
                }
                if (smooth(rule) || blends) {
                    next[child].taint = 1.0;
                    if (!fvar.empty() && children.DoesVertexFVarTopologyMatch(child, 0)) {
                        Far::ConstIndexArray faces = children.GetVertexFaces(child);
                        Far::ConstLocalIndexArray in = children.GetVertexFaceLocalIndices(child);
                        for (int i = 0; i < faces.size(); ++i) {
                            nextUvs[children.GetFaceFVarValues(faces[i], 0)[in[i]]].taint = 1.0;
                        }
                    }
                }
            }
        }
        level.swap(next);
        uvs.swap(nextUvs);
    }

    Far::TopologyLevel const &last = refiner->GetLevel(levels);
    for (Point const &p : level) {
        std::printf("v %.17g %.17g %.17g %.17g\n", p.x, p.y, p.z, p.taint);
    }
    for (Point const &p : uvs) {
        std::printf("vt %.17g %.17g %.17g\n", p.x, p.y, p.taint);
    }
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        if (last.IsFaceHole(f)) continue;
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        std::printf("f");
        for (int i = 0; i < fv.size(); ++i) {
            if (fvar.empty()) {
                std::printf(" %d", fv[i]);
            } else {
                std::printf(" %d/%d", fv[i], last.GetFaceFVarValues(f, 0)[i]);
            }
        }
        std::printf("\n");
    }
    delete refiner;
    return 0;
}
