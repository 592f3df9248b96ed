//! insta snapshots of the exact tables (radical form for quadratic fields, polynomials in ρ for
//! the others) of every shipped scheme, and of one generated source file. Reviewed and committed;
//! insta never writes snapshots under CI.

use lsubdiv::compiler::exact::codegen::generate;
use lsubdiv::compiler::exact::validity::analyse;
use lsubdiv::compiler::exact::{Scheme, Tables};
use lsubdiv_cli::{report, resolve};

fn report_of(name: &str) -> String {
    let r = resolve(name).unwrap();
    let a = analyse(&r.ls).unwrap();
    let s = Scheme::build(r.ls.clone()).unwrap();
    report::text(&r.ls, &a, Some(&s))
}

#[test]
fn exact_tables_of_shipped_schemes() {
    for name in lsubdiv_cli::builtin_names() {
        insta::assert_snapshot!(format!("inspect_{name}"), report_of(name));
    }
}

#[test]
fn generated_source_of_fibonacci_curve() {
    let r = resolve("fibonacci-curve").unwrap();
    let s = Scheme::build(r.ls).unwrap();
    insta::assert_snapshot!(
        "codegen_fibonacci_curve",
        generate(&Tables::new(s).unwrap())
    );
}

#[test]
fn transition_graph_of_binary_ternary() {
    let r = resolve("binary-ternary").unwrap();
    let s = Scheme::build(r.ls).unwrap();
    insta::assert_snapshot!("graph_binary_ternary", report::dot(&s));
}

#[test]
fn ev_tables_of_the_surface_schemes() {
    for name in ["binary-ternary", "fibonacci"] {
        let r = resolve(name).unwrap();
        let s = Scheme::build(r.ls).unwrap();
        let a = lsubdiv::compiler::exact::ev::analyse(&s).unwrap();
        let c = a.coefficients_f64();
        let rows: Vec<_> = (3..=16)
            .chain([20, 25])
            .map(|n| c.spectrum(n).unwrap())
            .collect();
        insta::assert_snapshot!(format!("ev_{name}"), report::ev_text(&s, &a, &rows));
    }
}
