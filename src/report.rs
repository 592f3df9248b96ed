//! What `lsubdiv inspect` and `lsubdiv graph` print: a text report, a JSON object, DOT.

use lsubdiv::compiler::exact::field::Elem;
use lsubdiv::compiler::exact::lsystem::LSystem;
use lsubdiv::compiler::exact::symmetry::MAX_INVOLUTIONS;
use lsubdiv::compiler::exact::validity::{Analysis, LengthSource};
use lsubdiv::compiler::exact::Scheme;
use serde_json::{json, Value};
use std::fmt::Write as _;

fn exact(e: &Elem) -> Value {
    json!({ "value": e.to_f64(), "exact": e.to_string() })
}

fn per_symbol(ls: &LSystem, v: &[Elem]) -> Value {
    Value::Object(
        ls.symbols
            .iter()
            .zip(v)
            .map(|(s, e)| (s.clone(), exact(e)))
            .collect(),
    )
}

fn source_name(s: LengthSource) -> &'static str {
    match s {
        LengthSource::Unique => "unique eigenvector",
        LengthSource::Declared => "declared in [lengths]",
        LengthSource::SymmetryInvariant => "sigma-invariant eigenvector ([G] Prop. 5.1)",
    }
}

/// The surface verdict of \[G\] §4 for `inspect`: the conditions with the step each starts from,
/// or the reason the scheme is refused for surfaces.
fn surface_json(ls: &LSystem, scheme: Option<&Scheme>) -> Value {
    let Some(s) = scheme else {
        return json!({ "ready": false, "reason": "no masks (invalid L-system or undetermined lengths)" });
    };
    match lsubdiv::compiler::exact::ev::analyse(s) {
        Ok(a) => json!({
            "ready": true,
                        "sigma": ls.symbols.iter().zip(&a.sigma)
                .map(|(s, &t)| (s.clone(), Value::String(ls.symbols[t as usize].clone())))
                .collect::<serde_json::Map<String, Value>>(),
            "sigma_declared": a.declared,
            "involutions": a.involutions.len(),
            "involutions_complete": a.involutions.len() < MAX_INVOLUTIONS,
            "stationary_from": a.stationary_from,
            "contained_from": a.contained_from,
        }),
        Err(e) => json!({ "ready": false, "reason": e.to_string() }),
    }
}

/// The JSON object of `inspect --json`. `scheme` is None when the L-system is invalid or its
/// lengths are undetermined (no masks then).
pub fn json(ls: &LSystem, a: &Analysis, scheme: Option<&Scheme>) -> Value {
    let minpoly: Vec<Value> = a
        .field
        .minpoly_integer()
        .iter()
        .map(|c| serde_json::from_str(&c.to_string()).unwrap_or(Value::Null))
        .collect();
    let rules: serde_json::Map<String, Value> = ls
        .symbols
        .iter()
        .zip(&ls.rules)
        .map(|(s, r)| (s.clone(), Value::String(ls.word_str(r))))
        .collect();
    let masks: Vec<Value> = scheme.map_or_else(Vec::new, |s| {
        s.graph
            .words
            .iter()
            .zip(&s.masks)
            .enumerate()
            .map(|(k, (w, m))| {
                let contributions: Vec<Value> = m
                    .contributions
                    .iter()
                    .enumerate()
                    .map(|(j, c)| {
                        json!({
                            "word": ls.word_str(&c.word),
                            "weight": c.weight.to_f64(),
                            "exact": c.weight.to_string(),
                            "child": m.child == Some(j),
                        })
                    })
                    .collect();
                json!({
                    "word": ls.word_str(&w.word),
                    "transitional": w.transitional,
                    "first_step": w.first_step,
                    "steps": if w.transitional { json!(w.steps) } else { Value::Null },
                    "contributions": contributions,
                    "limit": s.limits.get(k).map_or(Value::Null, |l| json!({
                        "position": l.position.iter().map(exact).collect::<Vec<_>>(),
                        "tangent": l.tangent.iter().map(exact).collect::<Vec<_>>(),
                    })),
                })
            })
            .collect()
    });
    let sccs: Vec<Value> = scheme.map_or_else(Vec::new, |s| {
        s.graph
            .sccs
            .iter()
            .map(|c| {
                json!(c
                    .iter()
                    .map(|&i| ls.word_str(&s.graph.words[i].word))
                    .collect::<Vec<_>>())
            })
            .collect()
    });
    json!({
        "name": ls.name,
        "degree": ls.degree,
        "symbols": ls.symbols,
        "rules": rules,
        "axiom": ls.word_str(&ls.axiom),
        "valid": a.valid,
        "reason": a.reason,
        "matrix": a.matrix,
        "rho": a.rho.to_f64(),
        "rho_exact": a.rho.to_string(),
        "minimal_polynomial": minpoly,
        "characteristic_polynomial": a.char_poly.to_string(),
        "strongly_connected": a.strongly_connected,
        "theorem_3_7": a.theorem_3_7,
        "eigenspace_dim": a.eigenspace_dim,
        "lengths": a.lengths.as_ref().map(|(l, _)| per_symbol(ls, l)),
        "lengths_source": a.lengths.as_ref().map(|(_, s)| source_name(*s)),
        "lengths_problem": a.lengths_problem,
        "left_eigenvectors": a.left.iter().map(|v| per_symbol(ls, v)).collect::<Vec<_>>(),
                "masks": masks,
        "sccs": sccs,
        "surface": surface_json(ls, scheme),
    })
}

/// The human-readable report of `inspect`.
pub fn text(ls: &LSystem, a: &Analysis, scheme: Option<&Scheme>) -> String {
    let mut s = String::new();
    let w = &mut s;
    let _ = writeln!(
        w,
        "scheme {} (degree {}), axiom {}",
        ls.name,
        ls.degree,
        ls.word_str(&ls.axiom)
    );
    for (sym, r) in ls.symbols.iter().zip(&ls.rules) {
        let _ = writeln!(w, "  {sym} -> {}", ls.word_str(r));
    }
    let _ = writeln!(w, "M = {:?}", a.matrix);
    let _ = writeln!(w, "characteristic polynomial: {}", a.char_poly);
    let _ = writeln!(
        w,
        "rho = {} ≈ {}, minimal polynomial {}",
        a.rho,
        a.rho.to_f64(),
        a.field.minpoly()
    );
    match &a.reason {
        None => {
            let _ = writeln!(w, "valid ([N] Definition 3.1)");
        }
        Some(r) => {
            let _ = writeln!(w, "INVALID: {r}");
        }
    }
    let _ = writeln!(
        w,
        "strongly connected: {}; Theorem 3.7 condition: {}; eigenspace dimension: {}",
        a.strongly_connected, a.theorem_3_7, a.eigenspace_dim
    );
    match (&a.lengths, &a.lengths_problem) {
        (Some((l, src)), _) => {
            let _ = writeln!(w, "lengths ({}):", source_name(*src));
            for (sym, e) in ls.symbols.iter().zip(l) {
                let _ = writeln!(w, "  {sym}: {e} ≈ {}", e.to_f64());
            }
        }
        (None, Some(p)) => {
            let _ = writeln!(w, "lengths: {p}");
        }
        (None, None) => {}
    }
    for (i, v) in a.left.iter().enumerate() {
        let entries: Vec<String> = ls
            .symbols
            .iter()
            .zip(v)
            .map(|(s, e)| format!("{s}: {e}"))
            .collect();
        let _ = writeln!(w, "left eigenvector {}: {}", i + 1, entries.join(", "));
    }
    if let Some(sc) = scheme {
        let tr = sc.graph.words.iter().filter(|w| w.transitional).count();
        let _ = writeln!(w, "{} masks ({} transitional):", sc.masks.len(), tr);
        for (k, (info, m)) in sc.graph.words.iter().zip(&sc.masks).enumerate() {
            let tag = if info.transitional {
                format!("  (transitional, steps {:?})", info.steps)
            } else {
                format!("  (from step {})", info.first_step)
            };
            let _ = writeln!(w, "  {}{tag}", ls.word_str(&m.word));
            for (j, c) in m.contributions.iter().enumerate() {
                let child = if m.child == Some(j) { "  <- child" } else { "" };
                let _ = writeln!(
                    w,
                    "    {}  {:>20}  = {}{child}",
                    ls.word_str(&c.word),
                    format!("{:.17}", c.weight.to_f64()),
                    c.weight
                );
            }
            if let Some(l) = sc.limits.get(k) {
                let list =
                    |v: &[Elem]| v.iter().map(Elem::to_string).collect::<Vec<_>>().join(", ");
                let _ = writeln!(w, "    limit point: {}", list(&l.position));
                let _ = writeln!(w, "    limit tangent: {}", list(&l.tangent));
            }
        }
        match lsubdiv::compiler::exact::ev::analyse(sc) {
            Ok(a) => {
                let _ = writeln!(
                    w,
                    "surfaces ([G] §4): ready; EV configuration stationary from step {} (Lemma 4.6 / Prop. 4.7), masks contained from step {} (Prop. 4.8)",
                    a.stationary_from, a.contained_from
                );
            }
            Err(e) => {
                let _ = writeln!(w, "surfaces ([G] §4): refused: {e}");
            }
        }
        for (i, c) in sc.graph.sccs.iter().enumerate() {
            let names: Vec<String> = c
                .iter()
                .map(|&j| ls.word_str(&sc.graph.words[j].word))
                .collect();
            let _ = writeln!(w, "SCC {}: {}", i + 1, names.join(" "));
        }
    }
    s
}

/// Fill colours of strongly connected components, by component index (DOT and pictures).
pub const SCC_FILLS: [&str; 6] = [
    "#cfe2ff", "#d1e7dd", "#fff3cd", "#f8d7da", "#e2d9f3", "#d3f1f4",
];

/// The transition graph in DOT: SCC members filled, transitional words dashed.
pub fn dot(s: &Scheme) -> String {
    let ls = &s.ls;
    let mut out = format!(
        "digraph \"{}\" {{\n  rankdir=LR;\n  node [shape=box, fontname=\"monospace\"];\n",
        dot_escape(&ls.name)
    );
    let in_scc: Vec<Option<usize>> = (0..s.graph.words.len())
        .map(|i| s.graph.sccs.iter().position(|c| c.contains(&i)))
        .collect();
    for (i, w) in s.graph.words.iter().enumerate() {
        let mut attrs = vec![format!("label=\"{}\"", dot_escape(&ls.word_str(&w.word)))];
        if let Some(c) = in_scc[i] {
            attrs.push(format!(
                "style=filled, fillcolor=\"{}\"",
                SCC_FILLS[c % SCC_FILLS.len()]
            ));
        }
        if w.transitional {
            attrs.push(format!("style=dashed, xlabel=\"steps {:?}\"", w.steps));
        }
        let _ = writeln!(out, "  w{i} [{}];", attrs.join(", "));
    }
    for (i, succ) in s.graph.edges.iter().enumerate() {
        for j in succ {
            let _ = writeln!(out, "  w{i} -> w{j};");
        }
    }
    out.push_str("}\n");
    out
}

/// `text` inside a DOT double-quoted string: `"` and `\` escaped, so that any symbol name
/// (scheme files allow both) gives well-formed DOT.
fn dot_escape(text: &str) -> String {
    text.replace('\\', "\\\\").replace('"', "\\\"")
}

/// The text report of `lsubdiv ev`: the EV conditions, the configuration per step, the exact
/// stationary stencils and the spectrum per valence.
pub fn ev_text(
    s: &Scheme,
    a: &lsubdiv::compiler::exact::ev::SurfaceAnalysis,
    rows: &[lsubdiv::runtime::ev::Spectrum],
) -> String {
    let ls = &s.ls;
    let mut out = String::new();
    let w = &mut out;
    let sigma: Vec<String> = a
        .sigma
        .iter()
        .enumerate()
        .filter(|(i, &t)| *i < t as usize)
        .map(|(i, &t)| format!("{}<->{}", ls.symbols[i], ls.symbols[t as usize]))
        .collect();
    let _ = writeln!(
        w,
        "scheme {}: sigma {} ({}; {}{} involution(s) make it symmetric)",
        ls.name,
        if sigma.is_empty() {
            "identity".into()
        } else {
            sigma.join(" ")
        },
        if a.declared { "declared" } else { "found" },
        if a.involutions.len() >= MAX_INVOLUTIONS {
            "at least "
        } else {
            ""
        },
        a.involutions.len()
    );
    let _ = writeln!(
        w,
        "EV configuration stationary from step {} ([G] Lemma 4.6 / Prop. 4.7); masks contained from step {} (Prop. 4.8)",
        a.stationary_from, a.contained_from
    );
    for st in &a.steps {
        let _ = writeln!(
            w,
            "  step {}: ray {}, radial word {}, contained {}, EV child divided by alpha + n * {} (≈ {:.12})",
            st.step,
            ls.word_str(&st.ray),
            ls.word_str(&st.radial_word),
            st.contained,
            st.ring_weight,
            st.ring_weight.to_f64()
        );
    }
    let names = [
        "EV -> r",
        "EV -> d",
        "R_k -> r_k",
        "R_k±1 -> r_k",
        "D -> r",
        "R -> d",
        "D_k -> d_k",
        "R -> EV",
        "D -> EV",
    ];
    let _ = writeln!(w, "stationary 1-ring stencils (exact):");
    for (n, (_, v)) in names.iter().zip(a.coefficients.named()) {
        let _ = writeln!(w, "  {n:>13}: {v} ≈ {:.12}", v.to_f64());
    }
    if !a.first_step_stencils.is_empty() {
        let _ = writeln!(
            w,
            "first-step stencils (masks not contained; products of the radial mask):"
        );
        for st in &a.first_step_stencils {
            let parts: Vec<String> = st
                .weights
                .iter()
                .map(|((i, j), v)| format!("({i},{j}): {v}"))
                .collect();
            let _ = writeln!(w, "  new point {:?}: {}", st.at, parts.join(", "));
        }
    }
    let _ = writeln!(
        w,
        "{:>4} {:>18} {:>18} {:>18} {:>18} {:>18}",
        "n", "alpha", "lambda1", "lambda2", "mu0", "normalisation"
    );
    for r in rows {
        let _ = writeln!(
            w,
            "{:>4} {:>18.15} {:>18.15} {:>18.15} {:>18.15} {:>18.15}",
            r.n, r.alpha, r.lambda1, r.lambda2, r.mu0, r.normalisation
        );
    }
    let _ = writeln!(
        w,
        "limit point from the stationary 1-ring (left eigenvector of eigenvalue 1; numeric, as alpha):"
    );
    let _ = writeln!(
        w,
        "{:>4} {:>18} {:>18} {:>18}",
        "n", "EV", "each radial", "each diagonal"
    );
    let ev = a.coefficients_f64();
    for r in rows {
        let [c, radial, diagonal] = ev.limit_weights(r.n, r.alpha);
        let _ = writeln!(w, "{:>4} {c:>18.15} {radial:>18.15} {diagonal:>18.15}", r.n);
    }
    out
}
