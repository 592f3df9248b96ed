//! The surface benchmark table: every standard mesh × scheme × path × thread count, run as
//! separate `lsubdiv bench` processes (so each peak RSS is its own), interleaved over repetitions,
//! printed as a markdown table with ratios measured in the same run:
//! generated/generic, 2 threads/1 thread, f32/f64, and peak RSS / essential memory
//! (input + output + one intermediate level), also with the program's code taken off the peak
//! (its resident pages mapped from files, `RssFile`), and peak RSS / what the size guard counts
//! for the run (`patch::footprint`: input, topology, tables, buffers, output positions); the
//! time of each phase and of each depth-first level (summed over the workers).
//!
//! `cargo bench --bench surfaces` (set LSUBDIV_BENCH_QUICK=1 for one repetition).

use serde_json::Value;
use std::collections::BTreeMap;
use std::process::Command;

fn run(args: &[String]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_lsubdiv"))
        .args(["bench", "--json"])
        .args(args)
        .output()
        .expect("lsubdiv bench runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Exact compilation time of every shipped scheme (analysis, masks, certificates, EV analysis,
/// codegen), median of 5, in milliseconds.
fn compile_times() {
    println!("| scheme | exact compile (ms) |");
    println!("|---|---|");
    for name in lsubdiv_cli::builtin_names() {
        let mut times: Vec<f64> = (0..5)
            .map(|_| {
                let start = std::time::Instant::now();
                let r = lsubdiv_cli::resolve(name).expect("shipped scheme");
                let s = lsubdiv::compiler::exact::Scheme::build(r.ls).expect("compiles");
                let t = lsubdiv::compiler::exact::Tables::new(s).unwrap();
                std::hint::black_box(lsubdiv::compiler::exact::codegen::generate(&t));
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        times.sort_by(f64::total_cmp);
        println!("| {name} | {:.1} |", times[2]);
    }
    println!();
}

/// This machine's own two-thread scaling, as a yardstick for the 2-thread column: the same
/// work on one thread, then twice that work on two, for a register-only loop and for a loop
/// that streams 400 MB through memory. Median of 3.
fn machine_scaling() {
    use std::hint::black_box;
    use std::time::Instant;
    fn alu(n: u64) -> f64 {
        let (mut x, mut y) = (1.0f64, 0.5f64);
        for i in 0..n {
            x = x * 1.000_000_1 + i as f64 * 1e-9;
            y = y * 0.999_999_9 + x * 1e-9;
        }
        x + y
    }
    fn stream(v: &mut [f64]) {
        for x in v.iter_mut() {
            *x = *x * 1.000_000_1 + 1.0;
        }
    }
    let (mut a, mut b) = (vec![1.0f64; 25_000_000], vec![1.0f64; 25_000_000]);
    let mut ratios = [Vec::new(), Vec::new()];
    for _ in 0..3 {
        let t = Instant::now();
        black_box(alu(200_000_000));
        let one = t.elapsed().as_secs_f64();
        let t = Instant::now();
        std::thread::scope(|s| {
            let h = s.spawn(|| alu(200_000_000));
            black_box(alu(200_000_000) + h.join().expect("thread"));
        });
        ratios[0].push(2.0 * one / t.elapsed().as_secs_f64());
        let t = Instant::now();
        stream(black_box(&mut a));
        let one = t.elapsed().as_secs_f64();
        let t = Instant::now();
        std::thread::scope(|s| {
            s.spawn(|| stream(black_box(&mut a)));
            stream(black_box(&mut b));
        });
        ratios[1].push(2.0 * one / t.elapsed().as_secs_f64());
    }
    let [alu, mem] = ratios.map(median);
    println!(
        "This machine's two-thread scaling (same run): {alu:.2}× on a register-only loop, {mem:.2}× on a memory-streaming loop.\n"
    );
}

fn main() {
    compile_times();
    machine_scaling();
    let reps = if std::env::var_os("LSUBDIV_BENCH_QUICK").is_some() {
        1
    } else {
        3
    };
    // A closed grid, EVs among ordinary faces, and a triangle mesh (every face at an EV).
    let meshes = ["torus:256:256", "cube", "star", "icosphere:4"];
    let schemes = ["uniform-binary", "binary-ternary", "fibonacci"];
    let mut configs: Vec<Vec<String>> = Vec::new();
    for mesh in meshes {
        for scheme in schemes {
            for (path, threads, f32) in [
                ("generated", 1, false),
                ("generic", 1, false),
                ("generated", 2, false),
                ("generated", 1, true),
            ] {
                let mut a = vec![
                    "--mesh",
                    mesh,
                    "--scheme",
                    scheme,
                    "--path",
                    path,
                    "--threads",
                ]
                .into_iter()
                .map(String::from)
                .collect::<Vec<_>>();
                a.push(threads.to_string());
                if f32 {
                    a.push("--f32".into());
                }
                configs.push(a);
            }
        }
    }
    // Interleave: every configuration once per repetition.
    let mut results: BTreeMap<usize, Vec<Value>> = BTreeMap::new();
    for _ in 0..reps {
        for (i, c) in configs.iter().enumerate() {
            results.entry(i).or_default().push(run(c));
        }
    }
    println!("| mesh | scheme | path | threads | scalar | steps | output vertices | M vertices/s | ms start / ordinary / fans | ms per depth-first level (worker time) | peak RSS MB | RSS / essential | (RSS − code) / essential | RSS / guard | vs generated 1-thread f64 |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut baseline: BTreeMap<(String, String), f64> = BTreeMap::new();
    for runs in results.values() {
        let first = &runs[0];
        let mvps = median(
            runs.iter()
                .map(|r| r["mvps"].as_f64().unwrap_or(0.0))
                .collect(),
        );
        let key = (
            first["mesh"].as_str().unwrap_or("").to_string(),
            first["scheme"].as_str().unwrap_or("").to_string(),
        );
        let is_base =
            first["path"] == "generated" && first["threads"] == 1 && first["scalar"] == "f64";
        if is_base {
            baseline.insert(key.clone(), mvps);
        }
        let phases: Vec<String> = ["start", "ordinary", "fans"]
            .iter()
            .map(|k| {
                format!(
                    "{:.1}",
                    first["phase_seconds"][k].as_f64().unwrap_or(0.0) * 1e3
                )
            })
            .collect();
        let levels: Vec<String> = first["level_seconds"]
            .as_array()
            .map(|a| {
                a.iter()
                    .map(|x| format!("{:.1}", x.as_f64().unwrap_or(0.0) * 1e3))
                    .collect()
            })
            .unwrap_or_default();
        let rss = first["peak_rss_bytes"].as_f64().unwrap_or(0.0);
        let code = first["file_rss_bytes"].as_f64().unwrap_or(0.0);
        let essential = first["essential_bytes"].as_f64().unwrap_or(1.0);
        let guard = first["guard_bytes"].as_f64().unwrap_or(1.0);
        let ratio = baseline
            .get(&key)
            .map_or("—".to_string(), |b| format!("{:.2}×", mvps / b));
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {:.1} | {} | {} | {:.0} | {:.2} | {:.2} | {:.2} | {} |",
            key.0,
            key.1,
            first["path"].as_str().unwrap_or(""),
            first["threads"],
            first["scalar"].as_str().unwrap_or(""),
            first["steps"],
            first["output_vertices"],
            mvps,
            phases.join(" / "),
            levels.join(" / "),
            rss / 1e6,
            rss / essential,
            (rss - code) / essential,
            rss / guard,
            ratio
        );
    }
}
