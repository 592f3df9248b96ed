use lsubdiv_compiler::{scheme, Scheme};
#[test]
fn smoke() {
    for f in [
        "fibonacci-curve",
        "uniform-binary",
        "binary-ternary",
        "fibonacci",
        "fibonacci-alt",
        "remark-5-3",
        "low-ratio",
        "delay-queue-3",
    ] {
        let p = format!("{}/../schemes/{f}.toml", env!("CARGO_MANIFEST_DIR"));
        let ls = scheme::load(std::path::Path::new(&p)).unwrap();
        let s = Scheme::build(ls, &p).unwrap_or_else(|e| panic!("{e}"));
        println!(
            "== {f}: rho={} ({}) minpoly {} lengths {:?} words {} transitional {}",
            s.analysis.rho,
            s.analysis.rho.to_f64(),
            s.analysis.field.minpoly(),
            s.lengths,
            s.masks.len(),
            s.graph.words.iter().filter(|w| w.transitional).count()
        );
        if f == "fibonacci-curve" || f == "binary-ternary" {
            for m in &s.masks {
                let cs: Vec<String> = m
                    .contributions
                    .iter()
                    .map(|c| format!("{}:{}", s.ls.word_str(&c.word), c.weight))
                    .collect();
                println!(
                    "  {} -> {} child {:?}",
                    s.ls.word_str(&m.word),
                    cs.join(", "),
                    m.child
                );
            }
        }
    }
}
