//! Extraordinary vertices (\[G\] §2.2.2, §4.2): the conditions an L-system needs for surfaces, the
//! EV configuration step by step, the exact stencils of the stationary 1-ring, and α.
//!
//! Every initial edge carries the axiom ω (one symmetric symbol). Read outward from an EV, the
//! edges of a radial line after s steps carry the *ray* π^s(ω ω ω …); its first (d+1)/2 symbols
//! are ξ_s and the EV's radial word is σ̄(ξ_s)ξ_s. Lines through an EV continue with the mirrored
//! labels (\[G\] §2.2.2: "the labels of edges beyond the EV are … the symmetric symbols").

use crate::exact::field::Elem;
use crate::exact::lsystem::{LSystem, Part, Sym, Word};
use crate::exact::pipeline::Scheme;
use crate::exact::symmetry::{involutions, is_symmetry};
use crate::exact::work;
use crate::Error;
use lsubdiv_runtime::ev::EvCoefficients;

/// The EV configuration at one step.
#[derive(Clone, Debug)]
pub struct StepInfo {
    /// Step s (the paper's step s + 1).
    pub step: usize,
    /// The first d labels of the ray.
    pub ray: Word,
    /// σ̄(ξ)ξ: the word of the EV along any radial line.
    pub radial_word: Word,
    /// Proposition 4.8 holds at this step (masks near the EV stay on its side).
    pub contained: bool,
    /// What each sector's ordinary neighbours give the EV child: (1 − h(0)²)/4, h(0) the child
    /// weight of the radial mask. The EV child is divided by α + n × this.
    pub ring_weight: Elem,
    /// What the EV child gets from each radial neighbour R_k and each diagonal D_k: (E1, E2),
    /// certified to sum to `ring_weight` (the 1-ring holds all the EV child's parents).
    pub ring: (Elem, Elem),
}

/// One first-step stencil: the new point at new-grid offset (a, b) from an old vertex, and the
/// weights of the old vertices at old-grid offsets (i, j) — products of radial mask entries.
#[derive(Clone, Debug)]
pub struct Stencil {
    /// New-grid offset of the new point from the old vertex.
    pub at: (usize, usize),
    /// ((i, j), weight) for every contributing old vertex.
    pub weights: Vec<((i64, i64), Elem)>,
}

/// Everything the surface pipeline derives for a scheme.
#[derive(Clone, Debug)]
pub struct SurfaceAnalysis {
    /// The involution used.
    pub sigma: Vec<Sym>,
    /// Whether σ was declared in the scheme file (else found).
    pub declared: bool,
    /// Every involution that makes the system symmetric (Remark 4.5), the first
    /// [`MAX_INVOLUTIONS`](crate::exact::symmetry::MAX_INVOLUTIONS) when there are more.
    pub involutions: Vec<Vec<Sym>>,
    /// Steps 0 ..= `stationary_from`.
    pub steps: Vec<StepInfo>,
    /// First step from which the EV configuration (and the local matrix) no longer changes
    /// (Lemma 4.6 / Proposition 4.7).
    pub stationary_from: usize,
    /// First step from which masks are contained (Proposition 4.8).
    pub contained_from: usize,
    /// Stationary 1-ring stencils, exact.
    pub coefficients: EvCoefficients<Elem>,
    /// Stencils of the first step, derived from products of the radial mask entries, when the
    /// first step is not contained (\[G\] Fig. 3, eqs. (6)–(7)).
    pub first_step_stencils: Vec<Stencil>,
}

impl SurfaceAnalysis {
    /// The stationary coefficients as f64, for the runtime's α solver.
    pub fn coefficients_f64(&self) -> EvCoefficients {
        self.coefficients.map(Elem::to_f64)
    }
}

/// What each sector's ordinary neighbours give the EV child whose radial mask has child weight
/// h(0): (1 − h(0)²)/4 (in the regular configuration the child gets h(0)² + 4 of these = 1).
pub fn ring_weight(h0: &Elem) -> Elem {
    let f = h0.field();
    Elem::one(f)
        .sub(&h0.mul(h0))
        .div(&Elem::int(f, 4))
        .expect("nonzero")
}

/// Proposition 4.8 for odd d at one step: among the first (d+1)/2 − 1 intervals of the ray, at
/// most one splits, and into at most two.
fn contained(ls: &LSystem, ray: &[Sym]) -> bool {
    let k = ls.degree.div_ceil(2) - 1;
    let splits: Vec<usize> = ray[..k]
        .iter()
        .map(|&s| ls.rules[s as usize].len())
        .filter(|&l| l > 1)
        .collect();
    splits.len() <= 1 && splits.iter().all(|&l| l <= 2)
}

/// Analyses a compiled scheme for surfaces, within the work bound of [`crate::exact::work`];
/// refuses with the failing condition named.
pub fn analyse(s: &Scheme) -> Result<SurfaceAnalysis, Error> {
    work::stage(&s.ls, "the surface analysis ([G] §4)", || {
        analyse_unbounded(s)
    })
}

fn analyse_unbounded(s: &Scheme) -> Result<SurfaceAnalysis, Error> {
    let ls = &s.ls;
    let refuse =
        |part: Part, message: String, hint: &str| Err(ls.error(part, message, Some(hint.into())));
    if ls.degree != 3 {
        return refuse(
            Part::Degree,
            format!(
                "surfaces need degree 3 (bicubic, [G] §2.2); this scheme has degree {}",
                ls.degree
            ),
            "set `degree = 3` for surfaces (curves take any degree)",
        );
    }
    if ls.axiom.len() != 1 {
        return refuse(
            Part::Axiom,
            format!(
                "surfaces label every initial edge with the axiom, which must be one symbol; it is {}",
                ls.word_str(&ls.axiom)
            ),
            "use a one-symbol axiom that is its own twin, e.g. `axiom = \"C\"`",
        );
    }
    let all = involutions(ls);
    // With several involutions and none declared (Remark 4.5), the first is used and all reported.
    let (sigma, declared) = match &ls.symmetry {
        Some(sig) if is_symmetry(ls, sig) => (sig.clone(), true),
        Some(_) => {
            return refuse(
                Part::Symmetry,
                "the declared σ does not make the L-system symmetric ([G] Proposition 4.2)".into(),
                "pair twin symbols so that each rule read backwards is its twin's rule",
            )
        }
        None => match all.first() {
            Some(sig) => (sig.clone(), false),
            None => {
                return refuse(
                    Part::Rules,
                    format!(
                        "not symmetric: no involution σ gives π(σ(A)) = σ̄(π(A)) for all A with σ({0}) = {0} ([G] Proposition 4.2)",
                        ls.word_str(&ls.axiom)
                    ),
                    "surfaces need a symmetric L-system ([G] §4.1): twin symbols whose rules are each other's read backwards, e.g. `L = \"LC\"`, `R = \"CR\"`",
                )
            }
        },
    };
    let d = ls.degree;
    let half = d.div_ceil(2);

    // Rays: prefix_{s+1} = first d symbols of π(prefix_s), from ω^d.
    let mut rays: Vec<Word> = vec![vec![ls.axiom[0]; d]];
    let stationary_from = loop {
        let last = rays.last().expect("non-empty");
        let next: Word = ls.rewrite(last)[..d].to_vec();
        if next == *last {
            break rays.len() - 1;
        }
        if let Some(p) = rays.iter().position(|r| *r == next) {
            return refuse(
                Part::Rules,
                format!(
                    "the labels around an EV never become stationary: the ray prefix cycles with period {} ([G] Lemma 4.6 / Proposition 4.7 fail)",
                    rays.len() - p
                ),
                "the first labels out of an EV must settle: choose rules so that π of the label next to the EV starts with that label",
            );
        }
        rays.push(next);
    };
    let stat = &rays[stationary_from];
    let first = stat[0];
    let pi_first = &ls.rules[first as usize];
    if pi_first.len() != 2 || pi_first[0] != first {
        return refuse(
            Part::Rule(first as usize),
            format!(
                "the label {} of edges leaving an EV must rewrite as {} X ([G] Lemma 4.6 with Proposition 4.8); it rewrites as {}",
                ls.symbols[first as usize],
                ls.symbols[first as usize],
                ls.word_str(pi_first)
            ),
            &format!(
                "make the rule of `{0}` two symbols starting with `{0}`, e.g. `{0} = \"{0}C\"`",
                ls.symbols[first as usize]
            ),
        );
    }
    let mut steps = Vec::new();
    for (step, ray) in rays.iter().enumerate() {
        let xi = &ray[..half];
        let radial_word: Word = ls
            .mirror(&sigma, xi)
            .into_iter()
            .chain(xi.iter().copied())
            .collect();
        let m = s.mask_of(&radial_word);
        let h0 = &m.contributions[m.child.expect("odd degree")].weight;
        let ring_weight = ring_weight(h0);
        // R_k along the ray reads σ(ξ0) ξ0 ξ1 ξ2 outward; the EV child is P = |π(ξ0)| back.
        let w1: Word = vec![sigma[ray[0] as usize], ray[0], ray[1], ray[2]];
        let m1 = s.mask_of(&w1);
        let back =
            m1.child.expect("odd degree") as isize - ls.rules[ray[0] as usize].len() as isize;
        let to_ev = usize::try_from(back).ok().map_or_else(
            || Elem::zero(&s.analysis.field),
            |j| m1.contributions[j].weight.clone(),
        );
        let ring = (to_ev.mul(h0), to_ev.mul(&to_ev));
        if ring.0.add(&ring.1) != ring_weight {
            return refuse(
                Part::Rules,
                format!(
                    "at step {step} the EV child has parents beyond its 1-ring (1-ring weights {} + {} ≠ {ring_weight})",
                    ring.0, ring.1
                ),
                "the masks near an EV must stay within its 1-ring ([G] Proposition 4.8): split the labels next to the EV less",
            );
        }
        steps.push(StepInfo {
            step,
            ray: ray.clone(),
            radial_word,
            contained: contained(ls, ray),
            ring_weight,
            ring,
        });
    }
    if !steps[stationary_from].contained {
        return refuse(
            Part::Rules,
            "masks are not contained near EVs in the stationary configuration ([G] Proposition 4.8)".into(),
            "among the first (d+1)/2 − 1 labels out of an EV at most one may split, and into at most two",
        );
    }
    let contained_from = (0..=stationary_from)
        .rev()
        .take_while(|&k| steps[k].contained)
        .last()
        .expect("the stationary step is contained");

    let coefficients = stationary_coefficients(s, &sigma, stat)?;
    let first_step_stencils = if steps[0].contained {
        Vec::new()
    } else {
        first_step(s, &steps[0].radial_word)
    };
    Ok(SurfaceAnalysis {
        sigma,
        declared,
        involutions: all,
        steps,
        stationary_from,
        contained_from,
        coefficients,
        first_step_stencils,
    })
}

/// The stationary 1-ring stencils from the masks of W_rad = σ̄(ξ0ξ1)ξ0ξ1 (EV, and R_k across the
/// ray) and W_1 = σ(ξ0)ξ0ξ1ξ2 (R_k along the ray, D_k both ways), with |π(ξ0)| = 2: the EV child
/// at new-grid (0,0), r_k at (1,0), d_k at (1,1); R_k's child at (2,0), D_k's at (2,2).
/// Certificates: rows r and d sum to exactly 1; R→EV + D→EV = (1 − h(0)²)/4.
fn stationary_coefficients(
    s: &Scheme,
    sigma: &[Sym],
    ray: &[Sym],
) -> Result<EvCoefficients<Elem>, Error> {
    let ls = &s.ls;
    let w_rad: Word = ls
        .mirror(sigma, &ray[..2])
        .into_iter()
        .chain(ray[..2].iter().copied())
        .collect();
    let w_1: Word = vec![sigma[ray[0] as usize], ray[0], ray[1], ray[2]];
    let at = |w: &Word, off: isize| -> Elem {
        let m = s.mask_of(w);
        let j = m.child.expect("odd degree") as isize + off;
        m.contributions[j as usize].weight.clone()
    };
    let (h0, h1) = (at(&w_rad, 0), at(&w_rad, 1));
    let (m1, m2) = (at(&w_1, -1), at(&w_1, -2));
    let c = EvCoefficients {
        ev_to_radial: h1.mul(&h0),
        ev_to_diagonal: h1.mul(&h1),
        radial_to_radial: m1.mul(&h0),
        side_to_radial: m2.mul(&h1),
        diagonal_to_radial: m1.mul(&m2),
        radial_to_diagonal: m1.mul(&h1),
        diagonal_to_diagonal: m1.mul(&m1),
        radial_to_ev: m2.mul(&h0),
        diagonal_to_ev: m2.mul(&m2),
    };
    let f = &s.analysis.field;
    let two = Elem::int(f, 2);
    let one = Elem::one(f);
    let row_r = c
        .ev_to_radial
        .add(&c.radial_to_radial)
        .add(&two.mul(&c.side_to_radial))
        .add(&two.mul(&c.diagonal_to_radial));
    let row_d = c
        .ev_to_diagonal
        .add(&two.mul(&c.radial_to_diagonal))
        .add(&c.diagonal_to_diagonal);
    let ring = c.radial_to_ev.add(&c.diagonal_to_ev);
    let expect_ring = ring_weight(&h0);
    if row_r != one || row_d != one || ring != expect_ring {
        return Err(ls.error(
            Part::Rules,
            format!(
                "certificate failed: stationary 1-ring rows sum to {row_r} and {row_d} (not 1) or the EV ring weight {ring} ≠ {expect_ring}"
            ),
            None,
        ));
    }
    Ok(c)
}

/// First-step stencils on the uniform initial grid (every line carries the radial word): the new
/// point at (a, b), 0 ≤ b ≤ a ≤ ⌊P/2⌋ with P = |π(ω)|, gets m[c + a − P·i]·m[c + b − P·j] from
/// the old vertex at old-grid (i, j).
fn first_step(s: &Scheme, radial: &Word) -> Vec<Stencil> {
    let m = s.mask_of(radial);
    let c = m.child.expect("odd degree") as i64;
    let p = s.ls.rules[s.ls.axiom[0] as usize].len() as i64;
    let len = m.contributions.len() as i64;
    let entry = |k: i64| {
        (0..len)
            .contains(&k)
            .then(|| m.contributions[k as usize].weight.clone())
    };
    let reach = len / p + 1;
    let mut out = Vec::new();
    for a in 0..=p / 2 {
        for b in 0..=a {
            let mut weights = Vec::new();
            for i in -reach..=reach {
                for j in -reach..=reach {
                    if let (Some(x), Some(y)) = (entry(c + a - p * i), entry(c + b - p * j)) {
                        weights.push(((i, j), x.mul(&y)));
                    }
                }
            }
            out.push(Stencil {
                at: (a as usize, b as usize),
                weights,
            });
        }
    }
    out
}
