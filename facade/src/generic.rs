//! The dynamic path: any scheme file at run time. It holds the compiler's one
//! [`Tables`] value, the same that generated code is emitted from, and appends the masks of
//! words the axiom never makes, computed exactly on demand ([`GenericScheme::prepare`]). The
//! runtime's drivers read both paths' tables alike, so both give the same bits.
//!
//! ```
//! use lsubdiv::generic::GenericScheme;
//! use lsubdiv::{compiler::exact::{scheme, Scheme}, Curve, CurveScheme};
//!
//! let text = "name = \"chaikin\"\ndegree = 2\naxiom = \"A\"\n[rules]\nA = \"AA\"\n";
//! let scheme = Scheme::build(scheme::parse("chaikin.toml", text)?)?;
//! let chaikin = GenericScheme::new(scheme)?;
//! let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
//! let coarse = Curve::with_axiom(&chaikin.tables(), square, true);
//! let fine = lsubdiv::refine(&chaikin, &coarse, 2)?;
//! assert_eq!(fine.points.len(), 16);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use lsubdiv_compiler::exact::ev::SurfaceAnalysis;
use lsubdiv_compiler::exact::lsystem::Word;
use lsubdiv_compiler::exact::{Scheme, Tables};
use lsubdiv_io::Error;
use lsubdiv_mesh::surface::{SurfaceScheme, SurfaceTables};
use lsubdiv_runtime::{Curve, CurveScheme, CurveTables};
use std::collections::HashSet;

/// A curve scheme whose tables are computed at run time.
#[derive(Clone, Debug)]
pub struct GenericScheme {
    tables: Tables,
}

impl GenericScheme {
    /// Tables of every word reachable from the axiom; the error says when computing them
    /// exceeds the exact work bound (`lsubdiv_compiler::exact::work`).
    pub fn new(scheme: Scheme) -> Result<GenericScheme, Error> {
        Ok(GenericScheme {
            tables: Tables::new(scheme)?,
        })
    }

    /// The exact scheme behind the tables.
    pub fn scheme(&self) -> &Scheme {
        self.tables.scheme()
    }

    /// Adds the masks of the curve's words and of every word reachable from them (nothing for
    /// a curve the tables cannot refine: refining it reports why). The error says when their
    /// masks exceed the exact work bound; the tables are then as they were.
    pub fn prepare<const D: usize>(&mut self, curve: &Curve<D>) -> Result<(), Error> {
        let t = self.tables.curve();
        if curve.check(&t).is_err() {
            return Ok(());
        }
        // Each distinct word once, in order of first appearance: a refined curve of millions
        // of points makes a few dozen.
        let mut seen = HashSet::new();
        let start: Vec<Word> = (0..curve.points.len())
            .map(|k| curve.word(k, t.degree))
            .filter(|w| !seen.contains(w) && seen.insert(w.clone()))
            .collect();
        self.tables.add_reachable(start)
    }
}

impl CurveScheme for GenericScheme {
    fn tables(&self) -> CurveTables<'_> {
        self.tables.curve()
    }
}

/// A surface scheme whose tables, surface data included, are computed at run time.
#[derive(Clone, Debug)]
pub struct GenericSurface {
    curve: GenericScheme,
}

impl GenericSurface {
    /// Checks the surface conditions (\[G\] §4.2) and prepares the tables; the error names the
    /// condition that fails.
    pub fn new(scheme: Scheme) -> Result<GenericSurface, Error> {
        match Compiled::new(scheme)? {
            Compiled::Surface(s) => Ok(s),
            Compiled::Curves(_, why) => Err(why),
        }
    }

    /// The surface analysis.
    pub fn analysis(&self) -> &SurfaceAnalysis {
        self.curve
            .tables
            .surface_analysis()
            .expect("checked by GenericSurface::new")
    }

    /// The exact scheme.
    pub fn scheme(&self) -> &Scheme {
        self.curve.scheme()
    }
}

impl CurveScheme for GenericSurface {
    fn tables(&self) -> CurveTables<'_> {
        self.curve.tables()
    }
}

impl SurfaceScheme for GenericSurface {
    fn surface(&self) -> SurfaceTables<'_> {
        self.curve
            .tables
            .surface()
            .expect("checked by GenericSurface::new")
    }
}

/// A scheme file's tables, computed once: a surface scheme, or a curve scheme with the reason
/// it refines curves only.
#[derive(Clone, Debug)]
pub enum Compiled {
    /// Curves only, and why (\[G\] §4.2).
    Curves(GenericScheme, Error),
    /// Curves and surfaces.
    Surface(GenericSurface),
}

impl Compiled {
    /// The tables of `scheme` ([`GenericScheme::new`]), sorted by what they refine.
    pub fn new(scheme: Scheme) -> Result<Compiled, Error> {
        let curve = GenericScheme::new(scheme)?;
        Ok(match curve.tables.curves_only() {
            Some(why) => {
                let why = why.clone();
                Compiled::Curves(curve, why)
            }
            None => Compiled::Surface(GenericSurface { curve }),
        })
    }

    /// The scheme's name.
    pub fn name(&self) -> &str {
        &self.curve().scheme().ls.name
    }

    /// The scheme for curves.
    pub fn curve(&self) -> &GenericScheme {
        match self {
            Compiled::Curves(c, _) => c,
            Compiled::Surface(s) => &s.curve,
        }
    }

    /// The scheme for surfaces, or why it refines curves only.
    pub fn surface(&self) -> Result<&GenericSurface, &Error> {
        match self {
            Compiled::Curves(_, why) => Err(why),
            Compiled::Surface(s) => Ok(s),
        }
    }
}
