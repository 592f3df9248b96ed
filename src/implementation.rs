//! Which implementation refines: the generated kernels of a shipped scheme (`lsubdiv-generated`)
//! or the generic table-driven path. Decided here only, for curves and surfaces alike.

use crate::Resolved;
use lsubdiv::compiler::Error;

/// The `--path` flag: what the user asked for. `auto`: the generated code when there is one,
/// else the generic path; `generated`: the generated code, an error when there is none;
/// `generic`: the generic table-driven path. (Plain comments on the variants: doc comments
/// would turn `--help` into its long form.)
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
#[allow(missing_docs)]
pub enum PathChoice {
    // Generated when there is one, else generic.
    Auto,
    // Generated, or an error.
    Generated,
    // Generic.
    Generic,
}

/// What refines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Implementation {
    /// The generated, specialised kernels (a shipped scheme at its own degree).
    Generated,
    /// The generic table-driven kernels.
    Generic,
}

impl Implementation {
    /// `generated` or `generic`.
    pub fn name(self) -> &'static str {
        match self {
            Implementation::Generated => "generated",
            Implementation::Generic => "generic",
        }
    }
}

/// What is refined: a curve, or a quad mesh (which needs a surface-capable scheme, \[G\] §4.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// A control polygon.
    Curve,
    /// A quad mesh.
    Surface,
}

impl PathChoice {
    /// The implementation this choice picks for `r`. Generated code exists for the shipped
    /// schemes given by name at their own degree (`Resolved::builtin`), and for surfaces only
    /// for the surface-capable ones.
    pub fn pick(self, r: &Resolved, geometry: Geometry) -> Result<Implementation, Error> {
        let generated = lsubdiv::generated::NAMES.contains(&r.ls.name.as_str())
            && (geometry == Geometry::Curve
                || lsubdiv::generated::SURFACE_NAMES.contains(&r.ls.name.as_str()));
        match self {
            PathChoice::Generic => Ok(Implementation::Generic),
            _ if r.builtin && generated => Ok(Implementation::Generated),
            PathChoice::Auto => Ok(Implementation::Generic),
            PathChoice::Generated => Err(Error::input(match geometry {
                Geometry::Curve => format!(
                    "`{}` has no generated code (only shipped schemes at their own degree do)",
                    r.ls.name
                ),
                Geometry::Surface => format!("`{}` has no generated surface code", r.ls.name),
            })),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_code_is_picked_for_shipped_schemes_at_their_own_degree() {
        let fib = crate::resolve("fibonacci").unwrap();
        let curve_only = crate::resolve("fibonacci-curve").unwrap();
        let mut other_degree = fib.clone();
        other_degree.builtin = false;
        use Implementation::{Generated, Generic};
        for (choice, r, geometry, expect) in [
            (PathChoice::Auto, &fib, Geometry::Curve, Ok(Generated)),
            (PathChoice::Auto, &fib, Geometry::Surface, Ok(Generated)),
            (PathChoice::Generic, &fib, Geometry::Curve, Ok(Generic)),
            (
                PathChoice::Auto,
                &other_degree,
                Geometry::Curve,
                Ok(Generic),
            ),
            (
                PathChoice::Generated,
                &other_degree,
                Geometry::Curve,
                Err("no generated code"),
            ),
            (
                PathChoice::Auto,
                &curve_only,
                Geometry::Curve,
                Ok(Generated),
            ),
            (
                PathChoice::Auto,
                &curve_only,
                Geometry::Surface,
                Ok(Generic),
            ),
            (
                PathChoice::Generated,
                &curve_only,
                Geometry::Surface,
                Err("no generated surface code"),
            ),
        ] {
            match (choice.pick(r, geometry), expect) {
                (Ok(got), Ok(want)) => assert_eq!(got, want),
                (Err(e), Err(want)) => assert!(e.message.contains(want), "{e}"),
                (got, want) => panic!("{choice:?} {geometry:?}: {got:?}, expected {want:?}"),
            }
        }
    }
}
