//! Acceptance data of the spine issue: the papers' values are expectations here, never inputs.
//! \[N\] = Nivoliers et al. 2012, \[G\] = Gérot & Ivrissimtzis 2023.

use lsubdiv_compiler::exact::field::{Elem, FieldRef};
use lsubdiv_compiler::exact::graph::reach;
use lsubdiv_compiler::exact::lsystem::LSystem;
use lsubdiv_compiler::exact::scheme;
use lsubdiv_compiler::exact::validity::analyse;
use lsubdiv_compiler::exact::Scheme;
use num_bigint::BigInt;

fn shipped(name: &str) -> Scheme {
    let p = format!("{}/../schemes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let ls = scheme::load(std::path::Path::new(&p)).expect("shipped scheme parses");
    Scheme::build(ls).unwrap_or_else(|e| panic!("{e}"))
}

fn system(text: &str) -> LSystem {
    scheme::parse("test.toml", text).unwrap_or_else(|e| panic!("{e}"))
}

fn two_symbols(r1: &str, r2: &str) -> LSystem {
    system(&format!(
        "name = \"t\"\ndegree = 3\naxiom = \"A1\"\n[rules]\nA1 = \"{r1}\"\nA2 = \"{r2}\"\n"
    ))
}

/// (a + b·√m)/den with √m given as an element of the field.
fn rad(sqrt_m: &Elem, a: i64, b: i64, den: i64) -> Elem {
    let f = sqrt_m.field();
    Elem::int(f, a)
        .add(&Elem::int(f, b).mul(sqrt_m))
        .div(&Elem::int(f, den))
        .expect("nonzero denominator")
}

fn minpoly(f: &FieldRef) -> Vec<i64> {
    f.minpoly_integer()
        .iter()
        .map(|c| i64::try_from(c.clone()).expect("small coefficient"))
        .collect()
}

#[test]
fn n_section_3_invalid_no_positive_eigenvector() {
    let a = analyse(&two_symbols("A1 A1 A2", "A2")).unwrap();
    assert!(!a.valid);
    assert!(a
        .reason
        .as_deref()
        .unwrap()
        .contains("no positive eigenvector"));
    assert_eq!(a.rho, Elem::int(&a.field, 2));
}

#[test]
fn n_section_3_invalid_rho_one() {
    let a = analyse(&two_symbols("A2", "A1")).unwrap();
    assert!(!a.valid);
    assert!(a.strongly_connected, "[N]: strongly connected yet invalid");
    assert!(!a.theorem_3_7);
    assert_eq!(a.rho, Elem::int(&a.field, 1));
    assert!(a.reason.as_deref().unwrap().contains("not greater than 1"));
}

#[test]
fn n_section_3_valid_not_strongly_connected() {
    let a = analyse(&two_symbols("A1 A2", "A2 A2 A2")).unwrap();
    assert!(a.valid, "{:?}", a.reason);
    assert!(!a.strongly_connected);
    assert_eq!(minpoly(&a.field), vec![-3, 1]);
    let (l, _) = a.lengths.unwrap();
    // [N]: eigenvector (1, 2) for ρ = 3.
    assert_eq!(l, vec![Elem::int(&a.field, 1), Elem::int(&a.field, 2)]);
}

#[test]
fn n_section_3_eigenspace_of_dimension_two() {
    let a = analyse(&two_symbols("A1 A1", "A2 A2")).unwrap();
    assert!(a.valid);
    assert_eq!(a.eigenspace_dim, 2);
    assert!(a.lengths.is_none());
    assert!(a.lengths_problem.unwrap().contains("not unique"));
    // Declared lengths are then accepted when they satisfy eq. (3)...
    let ok = system("name = \"t\"\ndegree = 2\naxiom = \"A1\"\n[rules]\nA1 = \"A1 A1\"\nA2 = \"A2 A2\"\n[lengths]\nA1 = \"1\"\nA2 = \"3/2\"\n");
    let a = analyse(&ok).unwrap();
    assert_eq!(
        a.lengths.unwrap().0[1],
        Elem::rational(&a.field, num_rational::BigRational::new(3.into(), 2.into()))
    );
    // ...and refused where the eigenvector is unique.
    let fixed = system("name = \"t\"\ndegree = 2\naxiom = \"L\"\n[rules]\nL = \"SL\"\nS = \"L\"\n[lengths]\nL = \"rho\"\nS = \"1\"\n");
    let e = analyse(&fixed).unwrap_err().to_string();
    assert!(e.contains("not free"), "{e}");
}

#[test]
fn n_fibonacci_lengths_left_eigenvector_and_lsl_mask() {
    let s = shipped("fibonacci-curve");
    let a = &s.analysis;
    assert!(a.valid && a.theorem_3_7 && a.strongly_connected);
    assert_eq!(minpoly(&a.field), vec![-1, -1, 1]);
    let phi = a.rho.clone();
    assert_eq!(s.lengths, vec![phi.clone(), Elem::one(&a.field)]);
    // [N] §3.3.3: s^T = [1/φ, 1/φ²].
    assert_eq!(a.left.len(), 1);
    assert_eq!(a.left[0][0], phi.inv().unwrap());
    assert_eq!(a.left[0][1], phi.mul(&phi).inv().unwrap());
    // [N] §2.2.1: LSL gives SLL: 2φ − 3, LLS: 1, LSL: 2 − φ.
    let lsl = s.ls.parse_word("LSL").unwrap();
    let m = s.mask_of(&lsl);
    let f = &a.field;
    let got: Vec<(String, Elem)> = m
        .contributions
        .iter()
        .map(|c| (s.ls.word_str(&c.word), c.weight.clone()))
        .collect();
    let two = Elem::int(f, 2);
    assert_eq!(
        got,
        vec![
            ("SLL".into(), two.mul(&phi).sub(&Elem::int(f, 3))),
            ("LLS".into(), Elem::one(f)),
            ("LSL".into(), two.sub(&phi)),
        ]
    );
}

#[test]
fn n_fibonacci_has_d_plus_2_recurring_words() {
    // [N] §2.2.2: d + 2 words in or reachable from the SCCs, for every degree.
    for d in 1..=8 {
        let mut ls = shipped("fibonacci-curve").ls;
        ls.degree = d;
        let g = reach(&ls, d + 1);
        let recurring = g.words.iter().filter(|w| !w.transitional).count();
        assert_eq!(recurring, d + 2, "degree {d}");
        Scheme::build(ls).unwrap_or_else(|e| panic!("degree {d}: {e}"));
    }
}

#[test]
fn n_delay_queue_rho_is_nth_root_of_two() {
    // [N] §3.4: ρ = 2^(1/n), a_i = ρ^(n−i), for n = 2..7.
    for n in 2..=7usize {
        let rules: String = (1..=n)
            .map(|i| {
                let rhs = if i == 1 {
                    format!("A{n} A{n}")
                } else {
                    format!("A{}", i - 1)
                };
                format!("A{i} = \"{rhs}\"\n")
            })
            .collect();
        let ls = system(&format!(
            "name = \"dq\"\ndegree = 3\naxiom = \"A1\"\n[rules]\n{rules}"
        ));
        let a = analyse(&ls).unwrap();
        assert!(a.valid && a.theorem_3_7, "n = {n}");
        let mut expect = vec![0i64; n + 1];
        expect[0] = -2;
        expect[n] = 1;
        assert_eq!(minpoly(&a.field), expect, "n = {n}");
        let (l, _) = a.lengths.clone().unwrap();
        for (i, li) in l.iter().enumerate() {
            assert_eq!(
                *li,
                a.rho.pow((n - 1 - i) as i64).unwrap(),
                "n = {n}, a_{}",
                i + 1
            );
        }
        assert!((a.rho.to_f64() - 2f64.powf(1.0 / n as f64)).abs() < 1e-15);
        Scheme::build(ls).unwrap();
    }
}

#[test]
fn uniform_binary_chaikin_and_cubic() {
    let mut ls = shipped("uniform-binary").ls;
    for (d, expect) in [
        (2, vec![(1, 4), (3, 4), (3, 4), (1, 4)]),
        (3, vec![(1, 8), (1, 2), (3, 4), (1, 2), (1, 8)]),
    ] {
        ls.degree = d;
        let s = Scheme::build(ls.clone()).unwrap();
        assert_eq!(s.masks.len(), 1);
        let f = &s.analysis.field;
        let got: Vec<Elem> = s.masks[0]
            .contributions
            .iter()
            .map(|c| c.weight.clone())
            .collect();
        let want: Vec<Elem> = expect
            .iter()
            .map(|&(p, q)| Elem::int(f, p).div(&Elem::int(f, q)).unwrap())
            .collect();
        assert_eq!(got, want, "degree {d}");
    }
}

/// A mask table: word → [(new word, a, b, den)] meaning (a + b√m)/den.
type Table = &'static [(&'static str, &'static [(&'static str, i64, i64, i64)])];

fn check_table(s: &Scheme, sqrt_m: &Elem, table: Table) {
    assert_eq!(s.masks.len(), table.len(), "number of words");
    for (word, entries) in table {
        let w = s.ls.parse_word(word).unwrap();
        let i = *s
            .graph
            .index
            .get(&w)
            .unwrap_or_else(|| panic!("{word} not reachable"));
        let m = &s.masks[i];
        let got: Vec<(String, Elem)> = m
            .contributions
            .iter()
            .map(|c| (s.ls.word_str(&c.word), c.weight.clone()))
            .collect();
        let want: Vec<(String, Elem)> = entries
            .iter()
            .map(|&(w, a, b, d)| (w.to_string(), rad(sqrt_m, a, b, d)))
            .collect();
        assert_eq!(got, want, "mask of {word}");
        // Odd degree: the child sits in the middle of a symmetric pair's layout.
        assert!(m.child.is_some());
    }
}

/// \[G\] Table A.5, transcribed from the paper (√ entries as (a, b, den)).
const TABLE_A5: Table = &[
    (
        "CLCR",
        &[
            ("LCRL", -11, 8, 7),
            ("CRLC", -17, 13, 7),
            ("RLCL", 9, -4, 7),
            ("LCLC", 46, -29, 7),
            ("CLCR", -24, 20, 7),
            ("LCRC", 6, -4, 1),
            ("CRCR", -7, 5, 1),
        ],
    ),
    (
        "LCRC",
        &[
            ("LCLC", -7, 5, 1),
            ("CLCR", 6, -4, 1),
            ("LCRC", -24, 20, 7),
            ("CRCR", 46, -29, 7),
            ("RCRL", 9, -4, 7),
            ("CRLC", -17, 13, 7),
            ("RLCR", -11, 8, 7),
        ],
    ),
    (
        "CRCR",
        &[
            ("LCRC", -11, 8, 7),
            ("CRCR", 10, -6, 7),
            ("RCRL", -2, 4, 7),
            ("CRLC", -46, 36, 7),
            ("RLCR", -24, 20, 7),
            ("LCRC", 6, -4, 1),
            ("CRCR", -7, 5, 1),
        ],
    ),
    (
        "LCLC",
        &[
            ("LCLC", -7, 5, 1),
            ("CLCR", 6, -4, 1),
            ("LCRL", -24, 20, 7),
            ("CRLC", -46, 36, 7),
            ("RLCL", -2, 4, 7),
            ("LCLC", 10, -6, 7),
            ("CLCR", -11, 8, 7),
        ],
    ),
    (
        "CRLC",
        &[
            ("LCRC", 10, -7, 2),
            ("CRCR", -4, 3, 1),
            ("RCRL", 2, -1, 1),
            ("CRLC", 5, -3, 1),
            ("RLCL", 2, -1, 1),
            ("LCLC", -4, 3, 1),
            ("CLCR", 10, -7, 2),
        ],
    ),
    (
        "CCCC",
        &[
            ("LCRL", -1, 1, 12),
            ("CRLC", -1, 2, 12),
            ("RLCR", 3, 1, 12),
            ("LCRL", 5, -1, 6),
            ("CRLC", 7, -2, 6),
            ("RLCR", 5, -1, 6),
            ("LCRL", 3, 1, 12),
            ("CRLC", -1, 2, 12),
            ("RLCR", -1, 1, 12),
        ],
    ),
    (
        "LCRL",
        &[
            ("LCLC", -7, 5, 1),
            ("CLCR", 6, -4, 1),
            ("LCRC", -20, 15, 2),
            ("CRCR", 12, -8, 1),
            ("RCRL", -1, 1, 1),
            ("CRLC", -4, 3, 2),
        ],
    ),
    (
        "RLCR",
        &[
            ("CRLC", -4, 3, 2),
            ("RLCL", -1, 1, 1),
            ("LCLC", 12, -8, 1),
            ("CLCR", -20, 15, 2),
            ("LCRC", 6, -4, 1),
            ("CRCR", -7, 5, 1),
        ],
    ),
    (
        "RCRL",
        &[
            ("CRLC", 10, -7, 1),
            ("RLCR", 6, -4, 1),
            ("LCRC", -20, 15, 2),
            ("CRCR", 12, -8, 1),
            ("RCRL", -1, 1, 1),
            ("CRLC", -4, 3, 2),
        ],
    ),
    (
        "RLCL",
        &[
            ("CRLC", -4, 3, 2),
            ("RLCL", -1, 1, 1),
            ("LCLC", 12, -8, 1),
            ("CLCR", -20, 15, 2),
            ("LCRL", 6, -4, 1),
            ("CRLC", 10, -7, 1),
        ],
    ),
];

#[test]
fn g_binary_ternary_table_a5() {
    let s = shipped("binary-ternary");
    let f = &s.analysis.field;
    assert_eq!(minpoly(f), vec![-1, -2, 1]);
    let sqrt2 = s.analysis.rho.sub(&Elem::one(f));
    assert_eq!(sqrt2.mul(&sqrt2), Elem::int(f, 2));
    // [G] §3.1: ℓ_L = ℓ_R = 1, ℓ_C = ρ − 1.
    assert_eq!(s.lengths, vec![Elem::one(f), sqrt2.clone(), Elem::one(f)]);
    check_table(&s, &sqrt2, TABLE_A5);
    let transitional: Vec<String> = s
        .graph
        .words
        .iter()
        .filter(|w| w.transitional)
        .map(|w| s.ls.word_str(&w.word))
        .collect();
    assert_eq!(transitional, vec!["CCCC"]);
}

/// \[G\] Table A.6, transcribed from the paper.
const TABLE_A6: Table = &[
    (
        "CDRL",
        &[("RLDR", 5, 1, 10), ("LDRL", -1, 1, 2), ("DRLC", -2, 1, 2)],
    ),
    (
        "RLCD",
        &[("DRLC", -2, 1, 2), ("RLCR", -1, 1, 2), ("LCRL", 5, 1, 10)],
    ),
    (
        "CLDR",
        &[("RLCL", 5, -1, 5), ("LCLD", 3, -1, 1), ("CLDR", -2, 1, 1)],
    ),
    (
        "LCRD",
        &[("LCRD", -2, 1, 1), ("CRDR", 3, -1, 1), ("RDRL", 5, -1, 5)],
    ),
    (
        "CRDR",
        &[("RDRL", 0, 1, 5), ("DRLD", -5, 3, 2), ("RLDR", -2, 1, 1)],
    ),
    (
        "LCLD",
        &[("LCRL", -2, 1, 1), ("CRLC", -5, 3, 2), ("RLCL", 0, 1, 5)],
    ),
    (
        "CRLC",
        &[("RDRL", 3, -1, 2), ("DRLC", 3, -1, 1), ("RLCR", 3, -1, 2)],
    ),
    (
        "DRLD",
        &[("LDRL", 3, -1, 2), ("DRLC", 3, -1, 1), ("RLCL", 3, -1, 2)],
    ),
    (
        "CRLD",
        &[("RDRL", 3, -1, 2), ("DRLC", 3, -1, 1), ("RLCL", 3, -1, 2)],
    ),
    (
        "DRLC",
        &[("LDRL", 3, -1, 2), ("DRLC", 3, -1, 1), ("RLCR", 3, -1, 2)],
    ),
    (
        "LCDR",
        &[("LCRL", 5, -1, 10), ("CRLD", 1, 0, 1), ("RLDR", 5, -1, 10)],
    ),
    (
        "SSSS",
        &[
            ("LRLR", 1, 0, 8),
            ("RLRL", 1, 0, 2),
            ("LRLR", 3, 0, 4),
            ("RLRL", 1, 0, 2),
            ("LRLR", 1, 0, 8),
        ],
    ),
    (
        "LCRL",
        &[
            ("LCRD", -2, 1, 1),
            ("CRDR", 3, -1, 1),
            ("RDRL", -1, 1, 2),
            ("DRLC", -2, 1, 2),
        ],
    ),
    (
        "RLDR",
        &[
            ("DRLC", -2, 1, 2),
            ("RLCL", -1, 1, 2),
            ("LCLD", 3, -1, 1),
            ("CLDR", -2, 1, 1),
        ],
    ),
    (
        "LDRL",
        &[
            ("LCLD", -2, 1, 1),
            ("CLDR", 3, -1, 1),
            ("LDRL", -1, 1, 2),
            ("DRLC", -2, 1, 2),
        ],
    ),
    (
        "RLCR",
        &[
            ("DRLC", -2, 1, 2),
            ("RLCR", -1, 1, 2),
            ("LCRD", 3, -1, 1),
            ("CRDR", -2, 1, 1),
        ],
    ),
    (
        "LRLR",
        &[
            ("LCDR", -5, 3, 12),
            ("CDRL", 5, -1, 6),
            ("DRLC", 7, -1, 6),
            ("RLCD", 5, -1, 6),
            ("LCDR", -5, 3, 12),
        ],
    ),
    (
        "RLRL",
        &[
            ("DRLC", -1, 1, 12),
            ("RLCD", 1, 1, 6),
            ("LCDR", 11, -3, 6),
            ("CDRL", 1, 1, 6),
            ("DRLC", -1, 1, 12),
        ],
    ),
    (
        "RDRL",
        &[
            ("DRLD", 7, -3, 2),
            ("RLDR", 3, -1, 1),
            ("LDRL", -1, 1, 2),
            ("DRLC", -2, 1, 2),
        ],
    ),
    (
        "RLCL",
        &[
            ("DRLC", -2, 1, 2),
            ("RLCR", -1, 1, 2),
            ("LCRL", 3, -1, 1),
            ("CRLC", 7, -3, 2),
        ],
    ),
];

#[test]
fn g_fibonacci_table_a6() {
    let s = shipped("fibonacci");
    let f = &s.analysis.field;
    assert_eq!(minpoly(f), vec![-1, -1, 1]);
    let sqrt5 = Elem::int(f, 2).mul(&s.analysis.rho).sub(&Elem::one(f));
    assert_eq!(sqrt5.mul(&sqrt5), Elem::int(f, 5));
    check_table(&s, &sqrt5, TABLE_A6);
    // [G] §3.2.1: the transitional words and the step each appears at (the paper counts steps
    // from 1: "initial step" = F_0, "2nd step" = F_1, ...).
    let mut transitional: Vec<(String, Vec<usize>)> = s
        .graph
        .words
        .iter()
        .filter(|w| w.transitional)
        .map(|w| (s.ls.word_str(&w.word), w.steps.clone()))
        .collect();
    transitional.sort();
    let mut expect: Vec<(String, Vec<usize>)> = [
        ("SSSS", 0),
        ("LRLR", 1),
        ("RLRL", 1),
        ("CDRL", 2),
        ("RLCD", 2),
        ("LCDR", 2),
        ("CRLD", 3),
    ]
    .iter()
    .map(|&(w, st)| (w.to_string(), vec![st]))
    .collect();
    expect.sort();
    assert_eq!(transitional, expect);
    // 13 classes up to mirror symmetry (σ: L↔R, C↔D).
    let sigma = s.ls.symmetry.clone().unwrap();
    let mut classes: Vec<Vec<u8>> = s
        .graph
        .words
        .iter()
        .map(|w| w.word.clone().min(s.ls.mirror(&sigma, &w.word)))
        .collect();
    classes.sort();
    classes.dedup();
    assert_eq!(classes.len(), 13);
}

#[test]
fn g_eq_43_and_48_cubic_fields() {
    // Remark 5.3, eq. (43): ρ ≈ 1.6956, x³ − x² − 2, 23 masks.
    let s = shipped("remark-5-3");
    assert_eq!(minpoly(&s.analysis.field), vec![-2, 0, -1, 1]);
    assert_eq!(s.masks.len(), 23);
    let r = s.analysis.rho.to_f64();
    assert!((r - 1.6956).abs() < 5e-5, "{r}");
    // The paper's closed form (1 + ∛(28 + √783) + ∛(28 − √783))/3 is the same number.
    let cardano = (1.0 + (28.0 + 783f64.sqrt()).cbrt() + (28.0 - 783f64.sqrt()).cbrt()) / 3.0;
    assert!((r - cardano).abs() < 1e-12, "{r} vs {cardano}");
    // Lengths ℓ_S = ρ² − ρ, ℓ_C = ℓ_D = 1, ℓ_L = ℓ_R = ρ (symbols S, L, C, D, R).
    let rho = &s.analysis.rho;
    let one = Elem::one(&s.analysis.field);
    assert_eq!(
        s.lengths,
        vec![
            rho.mul(rho).sub(rho),
            rho.clone(),
            one.clone(),
            one,
            rho.clone()
        ]
    );

    // eq. (48): ρ ≈ 1.4656, x³ − x² − 1, 31 masks.
    let s = shipped("low-ratio");
    assert_eq!(minpoly(&s.analysis.field), vec![-1, 0, -1, 1]);
    assert_eq!(s.masks.len(), 31);
    let r = s.analysis.rho.to_f64();
    let cardano =
        (1.0 + ((29.0 + 837f64.sqrt()) / 2.0).cbrt() + ((29.0 - 837f64.sqrt()) / 2.0).cbrt()) / 3.0;
    assert!(
        (r - 1.4656).abs() < 5e-5 && (r - cardano).abs() < 1e-12,
        "{r} vs {cardano}"
    );
    // ℓ_S = 2ρ, ℓ_C = ℓ_D = 1, ℓ_A = ℓ_B = ρ, ℓ_L = ℓ_R = ρ² (symbols S, L, C, A, D, B, R).
    let rho = &s.analysis.rho;
    let f = &s.analysis.field;
    let (one, r2) = (Elem::one(f), rho.mul(rho));
    assert_eq!(
        s.lengths,
        vec![
            Elem::int(f, 2).mul(rho),
            r2.clone(),
            one.clone(),
            rho.clone(),
            one,
            rho.clone(),
            r2
        ]
    );
}

#[test]
fn g_fibonacci_alt_uses_sigma_invariant_lengths() {
    // eq. (10) has a 2-dimensional eigenspace; Prop. 5.1 picks ℓ_L = ℓ_R, ℓ_C = ℓ_D.
    let s = shipped("fibonacci-alt");
    assert_eq!(s.analysis.eigenspace_dim, 2);
    let l = &s.lengths;
    assert_eq!(l[1], l[4]);
    assert_eq!(l[2], l[3]);
    // ℓ_S = (2/ρ)·ℓ_L (Prop. 5.2).
    assert_eq!(
        l[0],
        Elem::int(&s.analysis.field, 2)
            .div(&s.analysis.rho)
            .unwrap()
            .mul(&l[1])
    );
}

#[test]
fn minimal_polynomial_is_primitive_with_positive_leading_coefficient() {
    for name in [
        "fibonacci",
        "binary-ternary",
        "remark-5-3",
        "low-ratio",
        "delay-queue-3",
        "uniform-binary",
    ] {
        let s = shipped(name);
        let p = s.analysis.field.minpoly_integer();
        assert!(p.last().unwrap() > &BigInt::from(0));
        let g = p
            .iter()
            .fold(BigInt::from(0), |g, c| num_integer::Integer::gcd(&g, c));
        assert_eq!(g, BigInt::from(1), "{name}");
    }
}
