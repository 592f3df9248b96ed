//! [G] §5.2–5.3 and Appendix B: the family lists, recomputed exactly.
//!
//! Counting rule (see `explore`): masks are the reachable (d+1)-words, F_0 the factors of the
//! axiom repeated, a word and its mirror under the family's σ counted once.

use lsubdiv_compiler::exact::lsystem::{LSystem, Source};
use lsubdiv_explorer::{describe, enumerate, Enumeration, Family, Row};

fn rows(f: Family) -> Vec<Row> {
    enumerate(f, Enumeration::default()).unwrap()
}

fn find<'a>(rows: &'a [Row], pi_c: &str) -> &'a Row {
    rows.iter()
        .find(|r| r.pi_c == pi_c)
        .unwrap_or_else(|| panic!("π(C) = {pi_c} not listed"))
}

fn minpoly(r: &Row) -> Vec<String> {
    r.minimal_polynomial()
}

fn ints(v: &[i64]) -> Vec<String> {
    v.iter().map(ToString::to_string).collect()
}

/// 1 + √2: x² − 2x − 1.
const SILVER: [i64; 3] = [-1, -2, 1];
/// φ: x² − x − 1.
const GOLDEN: [i64; 3] = [-1, -1, 1];

#[test]
fn slcr_rows_of_appendix_b() {
    let r = rows(Family::Slcr);
    for (w, masks, m_row) in [("LCR", 10, [0, 1, 1, 1]), ("RCL", 17, [0, 1, 1, 1])] {
        let row = find(&r, w);
        assert_eq!(row.masks, masks, "{w}");
        assert_eq!(row.m_row, m_row, "{w}");
        assert_eq!(minpoly(row), ints(&SILVER), "{w}");
    }
    // (45) asks for a symmetric w: with K = 3 and integer ratios left out, LCR and RCL are all.
    let listed: Vec<&str> = r.iter().map(|r| r.pi_c.as_str()).collect();
    assert_eq!(listed, ["LCR", "RCL"]);
}

#[test]
fn slcdr_rows_of_section_5_3() {
    let r = rows(Family::Slcdr);
    for (w, masks, poly, m_row) in [
        ("DRL", 7, SILVER, [0, 1, 0, 1, 1]),
        ("L", 15, GOLDEN, [0, 1, 0, 0, 0]),
        ("RRD", 30, SILVER, [0, 0, 0, 1, 2]),
        ("LDR", 12, SILVER, [0, 1, 0, 1, 1]),
        ("LCR", 14, SILVER, [0, 1, 1, 0, 1]),
    ] {
        let row = find(&r, w);
        assert_eq!(row.masks, masks, "{w}");
        assert_eq!(row.m_row, m_row, "{w}");
        assert_eq!(minpoly(row), ints(&poly), "{w}");
        assert!(row.valid.is_ok(), "{w}");
    }
    // φ < 1 + √2: the golden rows come first, as in the paper's order.
    assert_eq!(r[0].minimal_polynomial(), ints(&GOLDEN));
}

/// The table printed under "Four symbols {S, L, C, R}" at ρ = (1+√13)/2 has π(C) over {L, R}
/// only and M[C] with a zero D-free column: its counts are those of family (47) (five symbols,
/// D = σ̄(C)), not (45). Seven of its eight rows are reproduced; LLR is printed 14, counted 13.
#[test]
fn the_sqrt13_table_is_family_47() {
    let r = rows(Family::Slcdr);
    let sqrt13 = ints(&[-3, -1, 1]);
    for (w, masks) in [
        ("RLR", 13),
        ("LRR", 14),
        ("LRL", 15),
        ("LLL", 17),
        ("RRR", 17),
        ("RRL", 18),
        ("RLL", 21),
        ("LLR", 13),
    ] {
        let row = find(&r, w);
        assert_eq!(row.masks, masks, "{w}");
        assert_eq!(minpoly(row), sqrt13, "{w}");
    }
}

/// Appendix B, {L, C, D, R}: LCR and LDR print 9 masks; counting CCCC (F_0, as SSSS is counted
/// for the S families, which is needed for DRL: 7) gives 10. Without F_0 it would be 9.
#[test]
fn lcdr_rows_count_the_initial_word() {
    let r = rows(Family::Lcdr);
    for w in ["LCR", "LDR"] {
        let row = find(&r, w);
        assert_eq!(row.masks, 10, "{w}");
        assert_eq!(minpoly(row), ints(&SILVER), "{w}");
    }
    assert_eq!(find(&r, "LCR").m_row, [1, 1, 0, 1]);
    assert_eq!(find(&r, "LDR").m_row, [1, 0, 1, 1]);
}

#[test]
fn lcr_has_one_non_integer_system() {
    let r = rows(Family::Lcr);
    assert_eq!(r.len(), 1);
    assert_eq!(r[0].pi_c, "LCR");
    assert_eq!(minpoly(&r[0]), ints(&SILVER));
    let all = enumerate(
        Family::Lcr,
        Enumeration {
            include_integer: true,
            ..Enumeration::default()
        },
    )
    .unwrap();
    // LR (ρ = 2) joins when integer ratios are included.
    assert!(all.iter().any(|r| r.pi_c == "LR" && r.integer));
}

fn system(symbols: &[&str], rules: &[&str], axiom: &str) -> LSystem {
    let symbols: Vec<String> = symbols.iter().map(|s| s.to_string()).collect();
    let parse = |w: &str| lsubdiv_compiler::exact::lsystem::parse_word(&symbols, w).unwrap();
    LSystem {
        name: "test".into(),
        degree: 3,
        rules: rules.iter().map(|w| parse(w)).collect(),
        axiom: parse(axiom),
        symbols,
        symmetry: None,
        lengths: None,
        source: Source::default(),
    }
}

#[test]
fn b1_two_symbols_four_masks() {
    // (B.1): L → LCL, C → L, axiom L, ρ = 1 + √2, 4 masks (LLLL, CLLC, CLLL, LCLL).
    let ls = system(&["L", "C"], &["LCL", "L"], "L");
    let r = describe("B.1", ls, String::new(), vec![], None).unwrap();
    assert_eq!(r.masks, 4);
    assert_eq!(minpoly(&r), ints(&SILVER));
}

#[test]
fn remark_5_3_and_eq_48_counts_are_raw_word_counts() {
    let ls = system(
        &["S", "L", "C", "D", "R"],
        &["CD", "LS", "L", "R", "SR"],
        "S",
    );
    let r = describe("43", ls, String::new(), vec![], None).unwrap();
    assert_eq!((r.words, r.masks), (23, 15));
    let ls = system(
        &["S", "L", "C", "A", "D", "B", "R"],
        &["LR", "LC", "A", "R", "B", "L", "DR"],
        "S",
    );
    let r = describe("48", ls, String::new(), vec![], None).unwrap();
    assert_eq!((r.words, r.masks), (31, 19));
    assert_eq!(minpoly(&r), ints(&[-1, 0, -1, 1]));
}

#[test]
fn surface_verdicts_follow_section_4_2() {
    let r = rows(Family::Slcdr);
    // DRL: symmetric (L↔R, C↔D), stationary and contained: a surface scheme.
    let drl = find(&r, "DRL");
    assert!(drl.surface.is_ok(), "{:?}", drl.surface);
    assert_eq!(drl.involution().unwrap(), "S L↔R C↔D");
    // Every listed system of (47) is symmetric by construction.
    assert!(r.iter().all(|r| r.sigma.is_some()));
}

fn small_search(require_surface: bool, asymmetric: bool) -> lsubdiv_explorer::Found {
    use lsubdiv_explorer::{search, Search};
    let opts = Search {
        symbols: 3,
        max_word_len: 2,
        rho_min: None,
        rho_max: None,
        max_masks: None,
        require_surface,
        include_integer: false,
        asymmetric,
        limit: 1_000_000,
        degree: 3,
    };
    search(&opts, &|_, _| {}).unwrap()
}

#[test]
fn search_front_is_a_pareto_front_and_round_trips_through_scheme_files() {
    let found = small_search(false, false);
    assert_eq!(u128::from(found.examined), found.space, "exhaustive");
    let front = &found.front;
    assert!(!front.is_empty());
    for w in front.windows(2) {
        // Strictly increasing ρ (exact), strictly decreasing masks: nobody dominates anybody.
        assert_eq!(
            w[0].field.cmp_generator(&w[1].field),
            std::cmp::Ordering::Less
        );
        assert!(w[0].masks > w[1].masks);
    }
    for r in front {
        assert!(r.valid.is_ok() && !r.integer);
        let text = lsubdiv_explorer::scheme_toml(r);
        let ls = lsubdiv_compiler::exact::scheme::parse("found.toml", &text).unwrap();
        let again = describe("search", ls, String::new(), vec![], None).unwrap();
        assert_eq!(again.masks, r.masks, "{text}");
        assert_eq!(again.minimal_polynomial(), r.minimal_polynomial(), "{text}");
    }
}

#[test]
fn search_with_surfaces_keeps_only_surface_schemes() {
    let found = small_search(true, false);
    assert!(found.front.iter().all(|r| r.surface.is_ok()));
}

#[test]
fn asymmetric_search_adds_rule_sets_without_involution() {
    let (sym, all) = (small_search(false, false), small_search(false, true));
    assert!(all.space > sym.space && all.candidates > sym.candidates);
    // The wider front is never worse: each symmetric front row is matched or dominated.
    for r in &sym.front {
        assert!(all
            .front
            .iter()
            .any(|a| { a.field.cmp_generator(&r.field).is_le() && a.masks <= r.masks }));
    }
}
