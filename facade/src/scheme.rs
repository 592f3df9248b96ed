//! A scheme as a value a program holds: one of the shipped schemes, compiled into
//! `lsubdiv-generated` and chosen by name ([`Scheme::shipped`]), or a scheme file compiled
//! exactly at run time ([`Scheme::from_file`], with the `compiler` feature). Curves refine with
//! it directly ([`Scheme::refine_curve`]); meshes through a plan ([`crate::Refiner`]).

use crate::Error;
use lsubdiv_generated::{AnyCurve, AnySurface};
use lsubdiv_mesh::surface::{SurfaceScheme, SurfaceTables};
use lsubdiv_runtime::{Curve, CurveContexts, CurveScheme, CurveTables};

/// A subdivision scheme: shipped, or compiled from a scheme file at run time. Cheap to clone
/// when shipped; a plan borrows it.
#[derive(Clone, Debug)]
pub struct Scheme {
    kind: Kind,
}

#[derive(Clone, Debug)]
enum Kind {
    /// Compiled into `lsubdiv-generated`: const tables and specialised kernels; its surface
    /// part, if it has one.
    Shipped(AnyCurve, Option<AnySurface>),
    /// Compiled by a program's build script (`include_scheme!`): its const tables, refined by
    /// the table-driven kernels.
    Tables(Box<(CurveTables<'static>, Option<SurfaceTables<'static>>)>),
    /// Compiled at run time: the tables of the exact pipeline.
    #[cfg(feature = "compiler")]
    File(Box<crate::generic::Compiled>),
}

impl Scheme {
    /// The shipped scheme called `name` (`lsubdiv::generated::NAMES`: `fibonacci`,
    /// `binary-ternary`, `uniform-binary`, …). No exact computation runs: its tables were
    /// compiled with lsubdiv.
    pub fn shipped(name: &str) -> Result<Scheme, Error> {
        match AnyCurve::named(name) {
            Some(s) => Ok(Scheme {
                kind: Kind::Shipped(s, AnySurface::named(name)),
            }),
            None => Err(Error::UnknownScheme {
                name: name.to_string(),
                shipped: lsubdiv_generated::NAMES.join(", "),
            }),
        }
    }

    /// A surface scheme a build script compiled (`lsubdiv_compiler::compile` in `build.rs`,
    /// then `lsubdiv::include_scheme!(my)`): `Scheme::compiled(&my::Scheme)`.
    pub fn compiled<S: SurfaceScheme>(scheme: &'static S) -> Scheme {
        Scheme {
            kind: Kind::Tables(Box::new((scheme.tables(), Some(scheme.surface())))),
        }
    }

    /// A curve scheme a build script compiled ([`Scheme::compiled`] for schemes that refine
    /// curves only).
    pub fn compiled_curve<S: CurveScheme>(scheme: &'static S) -> Scheme {
        Scheme {
            kind: Kind::Tables(Box::new((scheme.tables(), None))),
        }
    }

    /// The scheme of the scheme file at `path` (TOML: name, degree, axiom, rules; see the
    /// compiler's docs), compiled exactly: its errors name the file, line and column; a scheme
    /// whose exact computation exceeds the work bound is refused.
    #[cfg(feature = "compiler")]
    pub fn from_file(path: impl AsRef<std::path::Path>) -> Result<Scheme, Error> {
        use lsubdiv_compiler::exact::{scheme, Scheme as Exact};
        let ls = scheme::load(path.as_ref()).map_err(Error::Scheme)?;
        Scheme::from_exact(Exact::build(ls).map_err(Error::Scheme)?)
    }

    /// The scheme of an exact compilation (`lsubdiv::compiler::exact::Scheme::build`): its
    /// tables computed at run time.
    #[cfg(feature = "compiler")]
    pub fn from_exact(exact: lsubdiv_compiler::exact::Scheme) -> Result<Scheme, Error> {
        let compiled = crate::generic::Compiled::new(exact).map_err(Error::Scheme)?;
        Ok(Scheme {
            kind: Kind::File(Box::new(compiled)),
        })
    }

    /// Its name.
    pub fn name(&self) -> &str {
        match &self.kind {
            Kind::Shipped(s, _) => s.name(),
            Kind::Tables(t) => t.0.name,
            #[cfg(feature = "compiler")]
            Kind::File(c) => c.name(),
        }
    }

    /// Refines `curve` (labelled by [`Curve::with_axiom`] or by hand) `steps` times; the
    /// shipped schemes with their specialised kernels.
    pub fn refine_curve<const D: usize>(
        &self,
        curve: &Curve<D>,
        steps: usize,
    ) -> Result<Curve<D>, Error> {
        match &self.kind {
            Kind::Shipped(s, _) => lsubdiv_generated::refine_curve(s.name(), curve, steps)
                .expect("a shipped scheme is in the registry"),
            Kind::Tables(..) => lsubdiv_runtime::refine(self, curve, steps),
            #[cfg(feature = "compiler")]
            Kind::File(c) => lsubdiv_runtime::refine(c.curve(), curve, steps),
        }
        .map_err(|e| Error::Curve {
            scheme: self.name().to_string(),
            error: e,
        })
    }

    /// The step from which its surface masks are contained (\[G\] §4.3), or why it refines
    /// curves only: what predicting a mesh refinement's memory needs beside its tables.
    pub fn contained_from(&self) -> Result<usize, Error> {
        Ok(self.surface()?.surface().contained_from)
    }

    /// The scheme as a surface scheme, or why it refines curves only (\[G\] §4.2).
    pub(crate) fn surface(&self) -> Result<Surface<'_>, Error> {
        let curves_only = |why: lsubdiv_io::Error| Error::CurvesOnly {
            scheme: self.name().to_string(),
            why: Box::new(why),
        };
        let no_surface = || {
            lsubdiv_io::Error::input(
                "surfaces need a degree-3 scheme whose labels around an extraordinary vertex \
                 settle ([G] §4.2)",
            )
        };
        match &self.kind {
            Kind::Shipped(_, s) => s
                .as_ref()
                .map(Surface::Shipped)
                .ok_or_else(|| curves_only(no_surface())),
            Kind::Tables(t) => (t.1.as_ref())
                .map(|surface| Surface::Tables(&t.0, surface))
                .ok_or_else(|| curves_only(no_surface())),
            #[cfg(feature = "compiler")]
            Kind::File(c) => c
                .surface()
                .map(Surface::File)
                .map_err(|e| curves_only(e.clone())),
        }
    }
}

impl CurveScheme for Scheme {
    fn tables(&self) -> CurveTables<'_> {
        match &self.kind {
            Kind::Shipped(s, _) => s.tables(),
            Kind::Tables(t) => t.0,
            #[cfg(feature = "compiler")]
            Kind::File(c) => c.curve().tables(),
        }
    }

    fn contexts(&self) -> CurveContexts<'_> {
        match &self.kind {
            Kind::Shipped(s, _) => s.contexts(),
            Kind::Tables(..) => CurveContexts::NONE,
            #[cfg(feature = "compiler")]
            Kind::File(c) => c.curve().contexts(),
        }
    }
}

/// A scheme that refines surfaces, as the mesh refiner takes it: the shipped one's const
/// tables, or a scheme file's.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Surface<'s> {
    Shipped(&'s AnySurface),
    Tables(&'s CurveTables<'static>, &'s SurfaceTables<'static>),
    #[cfg(feature = "compiler")]
    File(&'s crate::generic::GenericSurface),
}

impl CurveScheme for Surface<'_> {
    fn tables(&self) -> CurveTables<'_> {
        match self {
            Surface::Shipped(s) => s.tables(),
            Surface::Tables(t, _) => **t,
            #[cfg(feature = "compiler")]
            Surface::File(s) => s.tables(),
        }
    }

    fn contexts(&self) -> CurveContexts<'_> {
        match self {
            Surface::Shipped(s) => s.contexts(),
            Surface::Tables(..) => CurveContexts::NONE,
            #[cfg(feature = "compiler")]
            Surface::File(s) => s.contexts(),
        }
    }
}

impl SurfaceScheme for Surface<'_> {
    fn surface(&self) -> SurfaceTables<'_> {
        match self {
            Surface::Shipped(s) => s.surface(),
            Surface::Tables(_, s) => **s,
            #[cfg(feature = "compiler")]
            Surface::File(s) => s.surface(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shipped_schemes_by_name_and_an_unknown_name_lists_them() {
        let fib = Scheme::shipped("fibonacci").unwrap();
        assert_eq!(fib.name(), "fibonacci");
        assert!(fib.surface().is_ok());
        let e = Scheme::shipped("fibonaci").unwrap_err();
        assert!(matches!(&e, Error::UnknownScheme { name, .. } if name == "fibonaci"));
        assert!(e.to_string().contains("binary-ternary"), "{e}");
        let curve = Scheme::shipped("fibonacci-curve").unwrap();
        assert!(matches!(curve.surface(), Err(Error::CurvesOnly { .. })));
    }

    #[test]
    fn a_curve_refines_alike_by_name_and_by_module() {
        let fib = Scheme::shipped("fibonacci").unwrap();
        let square = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let coarse = Curve::with_axiom(&fib.tables(), square, true);
        let by_name = fib.refine_curve(&coarse, 3).unwrap();
        let by_module =
            lsubdiv_runtime::refine(&lsubdiv_generated::fibonacci::Scheme, &coarse, 3).unwrap();
        assert_eq!(by_name, by_module);
    }
}
