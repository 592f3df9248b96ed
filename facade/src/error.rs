//! What can go wrong at the front door, as an enum a program can match: a bad file (where and
//! what, [`Diagnostic`]), a scheme that is unknown or refines curves only, a texture layout the
//! asked rule cannot refine, a refinement the mesh refiner refuses.

use lsubdiv_io::Error as Diagnostic;
use lsubdiv_mesh::facevarying::UvError;
use lsubdiv_mesh::surface::SurfaceError;
use lsubdiv_runtime::CurveError;
use std::fmt;

/// An error of the front door ([`crate::Scheme`], [`crate::Mesh`], [`crate::Refiner`]).
/// `Display` gives one line (a file's place first) and the hint, if any, on the next; no
/// `error:` prefix, so a program adds its own.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub enum Error {
    /// A file that cannot be read or written, or whose contents are wrong (a mesh's, a
    /// point file's): its place, what is wrong and, often, a hint.
    File(Diagnostic),
    /// A scheme file that is wrong, or whose exact computation is refused (work bound).
    Scheme(Diagnostic),
    /// No shipped scheme has this name.
    UnknownScheme {
        /// The name asked for.
        name: String,
        /// The shipped schemes' names, comma-separated.
        shipped: String,
    },
    /// The scheme refines curves only (\[G\] §4.2 names the conditions).
    CurvesOnly {
        /// The scheme.
        scheme: String,
        /// Which condition fails (for a scheme file: placed in it, with a hint).
        why: Box<Diagnostic>,
    },
    /// A curve the scheme cannot refine (labels it lacks, too few points).
    Curve {
        /// The scheme.
        scheme: String,
        /// What is wrong.
        error: CurveError,
    },
    /// The mesh's texture coordinates cannot be refined by the rule asked for (a smooth rule on
    /// a layout that is not a 2-manifold, coordinates that do not fit the faces); a program may
    /// fall back to `UvRule::Linear`.
    Uv {
        /// The mesh (its file, or the name it was given).
        mesh: String,
        /// What is wrong.
        error: UvError,
    },
    /// A mesh with faces other than quads, refined zero steps: its first step is a
    /// Catmull–Clark step, so it takes at least one.
    NoSteps {
        /// The mesh.
        mesh: String,
    },
    /// The limit surface asked for is not available after these steps (a semi-sharp feature
    /// still sharp, an extraordinary vertex before its configuration is stationary, a degree
    /// without limit masks): why, and how many steps it needs where that is the reason.
    NoLimit {
        /// The mesh.
        mesh: String,
        /// Why.
        why: String,
        /// How the steps were counted, when the mesh took a Catmull–Clark step first.
        note: Option<String>,
    },
    /// A refinement the mesh refiner refuses or cannot do (a result too large for 32-bit
    /// indices, a valence without α, a combination of features it does not refine, a limit
    /// asked before the step from which it is derived): why.
    Refine {
        /// The mesh.
        mesh: String,
        /// Why.
        error: SurfaceError,
        /// How the steps were counted, when the mesh took a Catmull–Clark step first.
        note: Option<String>,
    },
}

impl Error {
    /// Why [`Error::NoSteps`] is refused (its `Display` puts the mesh's name first).
    pub const NO_STEPS: &'static str = "the mesh has faces that are not quads: its first step is \
        a Catmull–Clark step, so it takes at least one step";

    /// How to fix it, when there is a hint.
    pub fn hint(&self) -> Option<&str> {
        match self {
            Error::File(d) | Error::Scheme(d) => d.hint.as_deref(),
            Error::CurvesOnly { why: d, .. } => d.hint.as_deref(),
            Error::NoSteps { .. } => Some("refine one step or more"),
            Error::NoLimit { .. } => Some("take the steps it names, or leave out the limit"),
            Error::UnknownScheme { .. } => Some("a scheme file needs `Scheme::from_file`"),
            Error::Uv {
                error: UvError::Layout(_),
                ..
            } => Some("refine the texture coordinates linearly (UvRule::Linear)"),
            _ => None,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::File(d) | Error::Scheme(d) => {
                if let Some(at) = &d.at {
                    write!(f, "{at}: ")?;
                }
                f.write_str(&d.message)?;
            }
            Error::UnknownScheme { name, shipped } => write!(
                f,
                "no shipped scheme is called `{name}` (shipped: {shipped})"
            )?,
            Error::CurvesOnly { scheme, why } => {
                write!(f, "`{scheme}` refines curves only: {}", why.message)?
            }
            Error::NoSteps { mesh } => write!(f, "{mesh}: {}", Error::NO_STEPS)?,
            Error::NoLimit { mesh, why, note } => {
                write!(f, "{mesh}: {why}")?;
                if let Some(note) = note {
                    write!(f, " ({note})")?;
                }
            }
            Error::Curve { scheme, error } => write!(f, "`{scheme}`: {error}")?,
            Error::Uv { mesh, error } => write!(f, "{mesh}: texture coordinates: {error}")?,
            Error::Refine { mesh, error, note } => {
                write!(f, "{mesh}: {error}")?;
                if let Some(note) = note {
                    write!(f, " ({note})")?;
                }
            }
        }
        if let Some(h) = self.hint() {
            write!(f, "\n  hint: {h}")?;
        }
        Ok(())
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::File(d) | Error::Scheme(d) => Some(d),
            Error::Curve { error, .. } => Some(error),
            Error::Uv { error, .. } => Some(error),
            Error::Refine { error, .. } => Some(error),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lsubdiv_io::Location;

    #[test]
    fn display_has_no_error_prefix_and_keeps_the_place_and_hint() {
        let at = Location {
            file: "cube.obj".into(),
            line: Some(3),
            column: None,
        };
        let e = Error::File(Diagnostic::at(at, "face has 2 vertices").with_hint("fix it"));
        assert_eq!(
            e.to_string(),
            "cube.obj:3: face has 2 vertices\n  hint: fix it"
        );
        assert!(format!("error: {e}").matches("error:").count() == 1);
    }
}
