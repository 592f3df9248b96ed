//! `lsubdiv render`: draws a quad mesh, closed or open, with the software renderer ([G] Fig. 6).

use crate::commands::args::MemoryLimit;
use crate::commands::subdivide::{approximate_note, refine_mesh, Limit, MeshJob};
use crate::commands::{load, one_stdin, threads};
use lsubdiv::compiler::Error;
use lsubdiv::mesh::topology::Topology;
use lsubdiv_cli::implementation::PathChoice;
use lsubdiv_cli::output::{format_by_extension, write_atomic};

/// Where the shading normals (and the curvature fit's points and normals) come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Normals {
    /// The limit surface's: the refined vertices taken to their limit points, with the limit
    /// normals there (needs --scheme; its default, where the limit is available).
    Limit,
    /// Averaged from the faces of the mesh drawn, the refined control mesh (the default
    /// without --scheme).
    Mesh,
}

/// Arguments of `lsubdiv render`.
#[derive(clap::Args)]
pub struct RenderArgs {
    /// An OBJ or PLY file (`-`: standard input), or a built-in mesh: `cube` (3-valent EVs),
    /// `grid-cube:K` (each face a K × K grid), `star` (EVs of valence 3, 5, 9), `torus:R:C`,
    /// `prism:N` (n-gon caps), `icosphere:L` (triangles); open `grid`, `tube`, `hole`,
    /// `pentagon-star`; `creased-cube`.
    mesh: String,
    /// Output image, `.png` or `.ppm`; PNG for a name without an extension (`-`: standard
    /// output). Written whole or not at all.
    #[arg(short, long)]
    output: std::path::PathBuf,
    /// Image size in pixels, WIDTHxHEIGHT.
    #[arg(long, default_value = "800x600")]
    size: String,
    #[arg(long, value_enum, default_value_t = lsubdiv_cli::render::Shading::Smooth)]
    shading: lsubdiv_cli::render::Shading,
    /// Draw the quad edges on top.
    #[arg(long)]
    wireframe: bool,
    /// `azimuth,elevation[,distance]`: degrees about the up axis (`--up`), degrees above the
    /// plane across it, distance in bounding-sphere radii (default 35,25 and the whole mesh in
    /// view).
    #[arg(long, allow_hyphen_values = true, conflicts_with = "eye")]
    camera: Option<String>,
    /// Which axis of the mesh points up in the picture: `y` (default for mesh files, OBJ's and
    /// PLY's usual convention), `z` (default for the built-in meshes), `x`, or `-x`, `-y`, `-z`.
    #[arg(long, value_enum, allow_hyphen_values = true)]
    up: Option<Up>,
    /// Camera position `x,y,z` instead of --camera.
    #[arg(long, allow_hyphen_values = true)]
    eye: Option<String>,
    /// Point looked at from --eye, `x,y,z` (default: the centre of the bounding box).
    #[arg(long, allow_hyphen_values = true, requires = "eye")]
    target: Option<String>,
    /// Refine the mesh with this scheme first (as `subdivide` does).
    #[arg(long, requires = "steps")]
    scheme: Option<String>,
    /// Subdivision steps before drawing.
    #[arg(long, requires = "scheme")]
    steps: Option<usize>,
    /// Shading normals and curvature: of the limit surface (default with --scheme, where the
    /// scheme has it after --steps; else a note and `mesh`) or of the mesh drawn (default, and
    /// the only choice, without --scheme).
    #[arg(long, value_enum)]
    normals: Option<Normals>,
    /// Curvature colours span [−R, R] (default: the 98th percentile of |H| over the vertices of
    /// the faces in view).
    #[arg(long)]
    curvature_range: Option<f64>,
    /// Worker threads for the refinement; default: all cores.
    #[arg(long, value_parser = crate::commands::args::thread_count)]
    threads: Option<usize>,
    #[command(flatten)]
    boundary: crate::commands::args::BoundaryArgs,
    #[command(flatten)]
    limit: MemoryLimit,
}

/// `--up`: the mesh's axis drawn upward.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Up {
    X,
    Y,
    Z,
    #[value(name = "-x")]
    MinusX,
    #[value(name = "-y")]
    MinusY,
    #[value(name = "-z")]
    MinusZ,
}

impl Up {
    /// A rotation taking this axis to +z (the renderer's up), as a map of points.
    fn to_z(self) -> impl Fn([f64; 3]) -> [f64; 3] {
        move |[x, y, z]| match self {
            Up::X => [y, z, x],
            Up::Y => [z, x, y],
            Up::Z => [x, y, z],
            Up::MinusX => [-y, z, -x],
            Up::MinusY => [z, -x, -y],
            Up::MinusZ => [-x, y, -z],
        }
    }
}

/// `lsubdiv render`: reads or builds the mesh, refines it if asked, draws it, writes the image
/// atomically. Reports the curvature range on stderr.
pub fn run(a: &RenderArgs) -> Result<(), Error> {
    use lsubdiv_cli::render::{self, camera::View, image::Format};
    let out_name = a.output.display().to_string();
    let format = format_by_extension(
        &a.output,
        "image",
        &[("png", Format::Png), ("ppm", Format::Ppm)],
    )?;
    if let Some(scheme) = &a.scheme {
        one_stdin(&[
            ("scheme", std::path::Path::new(scheme)),
            ("mesh", std::path::Path::new(&a.mesh)),
        ])?;
    }
    let (width, height) = lsubdiv_cli::picture::parse_size(&a.size)?;
    let (width, height) = (width as usize, height as usize);
    let numbers = render::parse_numbers;
    let view = match (&a.camera, &a.eye) {
        (_, Some(eye)) => {
            let eye = numbers("--eye", eye, 3..=3)?;
            let target = a
                .target
                .as_deref()
                .map(|t| numbers("--target", t, 3..=3))
                .transpose()?;
            View::LookAt {
                eye: [eye[0], eye[1], eye[2]],
                target: target.map(|t| [t[0], t[1], t[2]]),
            }
        }
        (Some(c), None) => {
            let v = numbers("--camera", c, 2..=3)?;
            View::Orbit {
                azimuth: v[0],
                elevation: v[1],
                distance: v.get(2).copied(),
            }
        }
        (None, None) => View::default(),
    };
    if let Some(r) = a.curvature_range {
        if !(r > 0.0 && r.is_finite()) {
            return Err(Error::input(format!(
                "--curvature-range {r}: expected a positive number"
            )));
        }
    }
    let limit = match (a.normals, &a.scheme) {
        (Some(Normals::Limit), None) => return Err(Error::input(
            "--normals limit needs --scheme and --steps: only a refined mesh has a limit surface",
        )
        .with_hint("add --scheme S --steps N, or use --normals mesh")),
        (Some(Normals::Limit), Some(_)) => Limit::On,
        (None, Some(_)) => Limit::IfAvailable,
        (Some(Normals::Mesh), _) | (None, None) => Limit::Off,
    };
    // The picture's buffers alone, before any mesh is read; again with the mesh before drawing.
    let samples = render::supersampling(width, height);
    let image_limit = |vertices: usize, quads: usize| {
        lsubdiv_cli::limits::render((width, height), samples, vertices, quads, a.limit.bytes())
    };
    image_limit(0, 0)?;
    let stages = lsubdiv_cli::progress::Stages::new(if a.scheme.is_some() { 4 } else { 3 });
    stages.next(format!("reading {}", a.mesh));
    let mut input = lsubdiv_cli::bench::mesh(&a.mesh, a.limit.bytes(), a.boundary.rule())?;
    // Mesh files are drawn +y up, the built-in meshes +z up, unless --up says otherwise.
    let file = a.mesh == "-" || std::path::Path::new(&a.mesh).is_file();
    let up = a.up.unwrap_or(if file { Up::Y } else { Up::Z });
    if up != Up::Z {
        let rotate = up.to_z();
        for p in &mut input.mesh.positions {
            *p = rotate(*p);
        }
    }
    let (mesh, topology, limit_normals) = match (&a.scheme, a.steps) {
        (Some(scheme), Some(steps)) => {
            stages.next(format!("refining: {steps} steps of {scheme}"));
            let job = MeshJob {
                name: &a.mesh,
                steps,
                path: PathChoice::Auto,
                threads: threads(a.threads),
                max_memory: a.limit.bytes(),
                limit,
                uv: false,
                // Drawn as the 2-manifold pieces a non-manifold mesh is refined as.
                join: false,
            };
            let fine = refine_mesh(&load(scheme, None)?, input, &job)?;
            if let Some(why) = &fine.limit_refused {
                stages.note(&format!(
                    "{}: note: shaded with the refined mesh's normals, not the limit surface's: {why}",
                    a.mesh
                ));
            }
            if let Some(note) = approximate_note(&a.mesh, &fine) {
                stages.note(&note);
            }
            // The refined mesh's own connectivity (a 2-manifold by construction: a non-manifold
            // mesh's pieces are not joined).
            let t =
                Topology::build(&fine.mesh).map_err(|e| Error::internal(None, e.to_string()))?;
            (fine.mesh, t, fine.normals)
        }
        _ => {
            if input.split {
                eprintln!(
                    "{}: warning: drawn after its first step, a Catmull–Clark step (it has faces that are not quads)",
                    a.mesh
                );
            }
            (input.mesh, input.topology, None)
        }
    };
    image_limit(mesh.positions.len(), mesh.faces.len())?;
    stages.next(format!("drawing {} quads", mesh.faces.len()));
    let scene = render::Scene::new(&mesh, &topology, limit_normals)
        .map_err(|e| Error::in_file(&a.mesh, e))?;
    let opts = render::Options {
        width,
        height,
        view,
        shading: a.shading,
        wireframe: a.wireframe,
        curvature_range: a.curvature_range,
    };
    let rendered = scene.render(&opts).map_err(Error::input)?;
    if let Some(r) = rendered.curvature {
        if !scene.orientable() {
            stages.note(&format!("{}: warning: the mesh is not orientable: the sign of the mean curvature flips across a seam", a.mesh));
        }
        let label = render::legend::label;
        let what = if r.relative {
            "mean curvature H times the bounding box's half side (H itself is beyond f64 at this scale)"
        } else {
            "mean curvature H"
        };
        let values = if r.finite == 0 {
            format!("{what}: no vertex in view has one")
        } else {
            format!("{what} in view from {} to {}", label(r.min), label(r.max))
        };
        stages.note(&format!(
            "{values}; colours span ±{} ({})",
            label(r.span),
            if r.percentile {
                "98th percentile of |H| over the vertices in view"
            } else {
                "--curvature-range"
            }
        ));
    }
    let bytes = rendered
        .image
        .encode(format)
        .map_err(|e| Error::internal(None, e))?;
    stages.next(format!("writing {out_name}"));
    write_atomic(&a.output, &bytes)
}
