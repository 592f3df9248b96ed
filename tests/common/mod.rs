//! Test support shared by integration tests (`mod common;`).
#![allow(dead_code)]
pub mod cli;

use lsubdiv::compiler::exact::{scheme, Scheme};
use lsubdiv::generic::GenericSurface;
use lsubdiv_testkit::fuzzing::{involution, SmallSystem};
use proptest::collection::vec;
use proptest::prelude::*;

/// The shipped schemes that refine surfaces (every one symmetric).
pub const SURFACE_SCHEMES: [&str; 7] = [
    "uniform-binary",
    "fibonacci",
    "fibonacci-alt",
    "binary-ternary",
    "found-cubic",
    "low-ratio",
    "remark-5-3",
];

/// The files of `../shared/NAME` (public data nobody on the project wrote), sorted; `None`
/// with a note saying what is `skipped` where the folder is absent.
pub fn shared_files(name: &str, skipped: &str) -> Option<Vec<std::path::PathBuf>> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared")
        .join(name);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        eprintln!("note: {} absent: {skipped}", dir.display());
        return None;
    };
    let mut files: Vec<_> = entries.map(|e| e.unwrap().path()).collect();
    files.sort();
    Some(files)
}

/// Deterministic pseudo-random numbers in [-1, 1).
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number.
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// `m` points of `D` coordinates.
    pub fn points<const D: usize>(&mut self, m: usize) -> Vec<[f64; D]> {
        (0..m)
            .map(|_| std::array::from_fn(|_| self.next()))
            .collect()
    }
}

/// Symmetric systems aimed at the surface conditions, shaped like the shipped ones: the
/// axiom S, fixed by σ, rewrites as L (a σ-fixed middle or nothing) R, L as L X (\[G\]
/// Lemma 4.6: the label next to an EV keeps its place), R as σ(X) R, and up to two more
/// symbols (paired or fixed) rewrite as random words of 1–3 symbols.
pub fn surface_systems() -> impl Strategy<Value = SmallSystem> {
    (0..=2usize)
        .prop_flat_map(|extra| {
            let symbol = 0..(3 + extra) as u8;
            (
                vec(symbol.clone(), 0..=1),
                symbol.clone(),
                vec(vec(symbol, 1..=3), extra),
                vec(0..3usize, 2),
            )
        })
        .prop_map(|(middle, x, extras, picks)| {
            let extra = extras.len();
            let mut rules = vec![[vec![1], middle, vec![2]].concat(), vec![1, x], vec![2]];
            rules.extend(extras);
            // σ: S fixed, L and R twins, the others paired or fixed as drawn.
            let sigma = [0, 2, 1]
                .into_iter()
                .chain(involution(extra, &picks).into_iter().map(|b| b + 3))
                .collect();
            SmallSystem {
                degree: 3,
                rules,
                axiom: vec![0],
                sigma: None,
            }
            .symmetrised(sigma)
        })
}

/// The knots of W_s, the axiom rewritten `steps` times: K_0 = 0, …, K_N, the prefix sums of
/// its symbols' exact interval lengths (as f64), in the parameter of the axiom's own length.
pub fn knots(s: &GenericSurface, steps: usize) -> Vec<f64> {
    use lsubdiv::CurveScheme;
    let t = s.tables();
    let mut knots = vec![0.0];
    for &a in &t.iterate(t.axiom, steps) {
        knots.push(knots[knots.len() - 1] + s.scheme().lengths[a as usize].to_f64());
    }
    knots
}

/// A drawn system's scheme text, its exact scheme and its surface scheme, if it is valid and
/// passes the surface conditions (\[G\] §4.2); not every drawn system does.
pub fn drawn_surface(sys: &SmallSystem) -> Option<(String, Scheme, GenericSurface)> {
    text_surface(sys.to_toml())
}

/// A scheme text's exact scheme and surface scheme, if it is valid and a surface scheme.
pub fn text_surface(text: String) -> Option<(String, Scheme, GenericSurface)> {
    let ls = scheme::parse("small.toml", &text).expect("the text parses");
    let exact = Scheme::build(ls).ok()?;
    let surface = GenericSurface::new(exact.clone()).ok()?;
    Some((text, exact, surface))
}

/// Surface schemes whose masks are contained near extraordinary, boundary and crease vertices
/// only from step 2 and 3 on (\[G\] Prop. 4.8): the axiom takes one or two steps (S → TCT,
/// S → T → U) before Binary-Ternary's rules, so on a mesh with features the refiner takes two
/// or three reference steps, each on its level cut along its sharp edges.
pub const DELAYED: [&str; 2] = [
    "name = \"delayed-once\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"T C T\"\n\
     T = \"L C R\"\nL = \"L C\"\nC = \"L C R\"\nR = \"C R\"\n[symmetry]\nL = \"R\"\n",
    "name = \"delayed-twice\"\ndegree = 3\naxiom = \"S\"\n[rules]\nS = \"T\"\nT = \"U\"\n\
     U = \"L C R\"\nL = \"L C\"\nC = \"L C R\"\nR = \"C R\"\n[symmetry]\nL = \"R\"\n",
];
