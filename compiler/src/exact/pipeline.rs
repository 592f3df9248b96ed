//! The exact pipeline: L-system → Q(ρ) → lengths → masks → graph, with the certificates that
//! make compilation fail when an identity that must hold exactly does not.

use crate::exact::field::Elem;
use crate::exact::graph::{reach, Reach};
use crate::exact::limit::{self, limit_mask, LimitMask};
use crate::exact::lsystem::{LSystem, Part, Sym, Word};
use crate::exact::masks::{mask, Mask};
use crate::exact::symmetry::check_symmetry;
use crate::exact::validity::{analyse, Analysis};
use crate::exact::work;
use crate::Error;
use std::borrow::Cow;

/// A compiled scheme: every reachable mask, exact.
#[derive(Clone, Debug)]
pub struct Scheme {
    /// The L-system.
    pub ls: LSystem,
    /// \[N\] §3 analysis.
    pub analysis: Analysis,
    /// Interval lengths a (smallest 1).
    pub lengths: Vec<Elem>,
    /// Reachable (d+1)-words and their transitions.
    pub graph: Reach,
    /// One mask per word of `graph.words`, same order.
    pub masks: Vec<Mask>,
    /// One limit mask per word of `graph.words` ([`crate::exact::limit`]), same
    /// order; empty for the degrees without one.
    pub limits: Vec<LimitMask>,
}

impl Scheme {
    /// Analyses, derives every reachable mask and checks the certificates, within the work bound
    /// of [`crate::exact::work`].
    pub fn build(ls: LSystem) -> Result<Scheme, Error> {
        let stage = ls.clone();
        work::stage(&stage, "the masks ([N] §2.2)", || {
            Scheme::build_unbounded(ls)
        })
    }

    fn build_unbounded(ls: LSystem) -> Result<Scheme, Error> {
        let analysis = analyse(&ls)?;
        let lengths = analysis.require_lengths(&ls)?.to_vec();
        if let Some(sigma) = &ls.symmetry {
            check_symmetry(&ls, sigma)?;
        }
        let graph = reach(&ls, ls.degree + 1);
        let masks = graph
            .words
            .iter()
            .map(|w| mask(&ls, &lengths, &w.word))
            .collect();
        let limits = graph
            .words
            .iter()
            .map_while(|w| limit_mask(&ls, &lengths, &w.word))
            .collect();
        let scheme = Scheme {
            ls,
            analysis,
            lengths,
            graph,
            masks,
            limits,
        };
        scheme.certify_partition_of_unity()?;
        scheme.certify_mirror()?;
        for m in &scheme.limits {
            limit::certify(&scheme.ls, &scheme.lengths, m).map_err(|e| scheme.internal(e))?;
        }
        Ok(scheme)
    }

    /// The mask of any (d+1)-word, borrowed from the table or computed now (words the axiom
    /// never makes).
    pub fn mask_of(&self, w: &[Sym]) -> Cow<'_, Mask> {
        match self.graph.index.get(w) {
            Some(&i) => Cow::Borrowed(&self.masks[i]),
            None => Cow::Owned(mask(&self.ls, &self.lengths, w)),
        }
    }

    /// A failed certificate: a bug in the compiler, reported with the scheme it concerns.
    fn internal(&self, message: String) -> Error {
        Error::internal(Some(self.ls.locate(Part::Rules)), message)
    }

    /// Every new point's incoming weights sum to exactly 1, for every reachable neighbourhood.
    ///
    /// A new point starting in π(u_d) of a (2d+1)-window u has all its parents among the d+1
    /// old points of u (their supports must contain its support), so the reachable
    /// (2d+1)-windows cover every configuration.
    fn certify_partition_of_unity(&self) -> Result<(), Error> {
        let d = self.ls.degree;
        let windows = reach(&self.ls, 2 * d + 1);
        for w in &windows.words {
            let u = &w.word;
            let mut offsets = vec![0usize];
            for &s in u {
                offsets.push(offsets.last().expect("non-empty") + self.ls.rules[s as usize].len());
            }
            for l in offsets[d]..offsets[d + 1] {
                let mut sum = Elem::zero(&self.analysis.field);
                for k in 0..=d {
                    if offsets[k] <= l && l + d < offsets[k + d + 1] {
                        let m = self.mask_of(&u[k..k + d + 1]);
                        sum = sum.add(&m.contributions[l - offsets[k]].weight);
                    }
                }
                if sum != Elem::one(&self.analysis.field) {
                    return Err(self.internal(format!(
                        "certificate failed: the weights of new point {} of π({}) sum to {sum}, not 1",
                        l - offsets[d],
                        self.ls.word_str(u)
                    )));
                }
            }
        }
        Ok(())
    }

    /// For a symmetric system: the mask of σ̄(w) is the mask of w reversed, words mirrored.
    fn certify_mirror(&self) -> Result<(), Error> {
        let Some(sigma) = &self.ls.symmetry else {
            return Ok(());
        };
        for m in &self.masks {
            let mirrored = self.mask_of(&self.ls.mirror(sigma, &m.word));
            let expect: Vec<(Word, &Elem)> = m
                .contributions
                .iter()
                .rev()
                .map(|c| (self.ls.mirror(sigma, &c.word), &c.weight))
                .collect();
            let got: Vec<(Word, &Elem)> = mirrored
                .contributions
                .iter()
                .map(|c| (c.word.clone(), &c.weight))
                .collect();
            let child_ok = match (m.child, mirrored.child) {
                (Some(a), Some(b)) => a + b + 1 == m.contributions.len(),
                (a, b) => a == b,
            };
            if got != expect || !child_ok {
                return Err(self.internal(format!(
                    "certificate failed: the mask of {} is not the mirror of the mask of {}",
                    self.ls.word_str(&mirrored.word),
                    self.ls.word_str(&m.word)
                )));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::scheme;

    fn binary_ternary() -> Scheme {
        let text = "name = \"bt\"\ndegree = 3\naxiom = \"C\"\n[rules]\nL = \"LC\"\nC = \"LCR\"\nR = \"CR\"\n[symmetry]\nL = \"R\"\n";
        Scheme::build(scheme::parse("bt.toml", text).unwrap()).unwrap()
    }

    #[test]
    fn partition_of_unity_certificate_catches_a_wrong_weight() {
        let mut s = binary_ternary();
        assert!(s.certify_partition_of_unity().is_ok());
        let w = &mut s.masks[3].contributions[1].weight;
        *w = w.add(
            &Elem::int(w.field(), 1)
                .div(&Elem::int(w.field(), 1000))
                .unwrap(),
        );
        let e = s.certify_partition_of_unity().unwrap_err().to_string();
        assert!(
            e.contains("certificate failed") && e.contains("not 1"),
            "{e}"
        );
    }

    #[test]
    fn mirror_certificate_catches_an_asymmetric_mask() {
        let mut s = binary_ternary();
        assert!(s.certify_mirror().is_ok());
        let m = &mut s.masks[4];
        m.contributions.swap(0, 1);
        let e = s.certify_mirror().unwrap_err().to_string();
        assert!(e.contains("is not the mirror"), "{e}");
    }
}
