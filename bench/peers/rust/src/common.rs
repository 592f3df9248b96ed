//! Shared by the three Rust harness binaries (lsubdiv-peers and the two peer crates, which
//! include this file with `#[path]`): argument parsing, OBJ input, timing, result lines and the
//! binary dump format that the accuracy check reads (the C++ harness writes the same format).
//!
//! Dump format (little-endian): 8 bytes magic `LSPEERS1`, u64 vertex count, u64 face count,
//! vertex count × 3 f64 (x y z), face count × 4 u32 (0-based corner indices).

#![allow(dead_code)]

use std::io::{BufWriter, Read, Write};
use std::time::Instant;

/// `--key value` options after the subcommand.
pub struct Args {
    pairs: Vec<(String, String)>,
}

impl Args {
    pub fn parse(args: &[String]) -> Result<Args, String> {
        let mut pairs = Vec::new();
        let mut it = args.iter();
        while let Some(k) = it.next() {
            let Some(key) = k.strip_prefix("--") else {
                return Err(format!("unexpected argument `{k}`"));
            };
            let v = it.next().ok_or_else(|| format!("`{k}` needs a value"))?;
            pairs.push((key.to_string(), v.clone()));
        }
        Ok(Args { pairs })
    }
    pub fn get(&self, key: &str) -> Option<&str> {
        self.pairs
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    pub fn req(&self, key: &str) -> Result<&str, String> {
        self.get(key).ok_or_else(|| format!("missing --{key}"))
    }
    pub fn usize(&self, key: &str, default: usize) -> Result<usize, String> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => v
                .parse()
                .map_err(|_| format!("--{key}: `{v}` is not a count")),
        }
    }
    pub fn f64(&self, key: &str, default: f64) -> Result<f64, String> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => v
                .parse()
                .map_err(|_| format!("--{key}: `{v}` is not a number")),
        }
    }
    /// The options of every harness's timed run.
    pub fn run(&self) -> Result<Run<'_>, String> {
        let obj = self.req("obj")?;
        Ok(Run {
            obj,
            name: self.get("name").unwrap_or(obj),
            levels: self.usize("levels", 3)?,
            runs: self.usize("runs", 7)?,
        })
    }
}

/// `--obj M.obj --name N --levels L --runs R` (name defaults to the OBJ path, levels to 3,
/// runs to 7).
pub struct Run<'a> {
    pub obj: &'a str,
    pub name: &'a str,
    pub levels: usize,
    pub runs: usize,
}

/// A quad mesh read from OBJ (`v x y z`, `f a b c d` with 1-based indices, `a/t/n` allowed).
pub struct Obj {
    pub positions: Vec<[f64; 3]>,
    pub faces: Vec<[u32; 4]>,
}

pub fn read_obj(path: &str) -> Result<Obj, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut positions = Vec::new();
    let mut faces = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let mut t = line.split_whitespace();
        let bad = |what: &str| format!("{path}:{}: {what}", n + 1);
        match t.next() {
            Some("v") => {
                let mut p = [0.0; 3];
                for c in &mut p {
                    *c = t
                        .next()
                        .and_then(|s| s.parse().ok())
                        .ok_or_else(|| bad("bad vertex"))?;
                }
                positions.push(p);
            }
            Some("f") => {
                let idx: Vec<u32> = t
                    .map(|s| s.split('/').next().unwrap_or("").parse::<u32>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| bad("bad face index"))?;
                let [a, b, c, d] = idx[..] else {
                    return Err(bad("face is not a quad"));
                };
                faces.push([a - 1, b - 1, c - 1, d - 1]);
            }
            // Sharp-feature tags: these harnesses cannot pass them on, and refining without
            // them would time another surface.
            Some("t") => return Err(bad("sharp-feature tags are not read by this harness")),
            _ => {}
        }
    }
    Ok(Obj { positions, faces })
}

/// One warm-up call, then the median wall time of `runs` calls (at least 1).
pub fn median_time(runs: usize, mut f: impl FnMut()) -> f64 {
    f();
    let mut times: Vec<f64> = (0..runs.max(1))
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

/// The line run.sh collects: `RESULT impl=… mesh=… levels=… out_vertices=… median_s=… mvps=…`.
pub fn report(imp: &str, mesh: &str, levels: usize, out_vertices: usize, median_s: f64) {
    println!(
        "RESULT impl={imp} mesh={mesh} levels={levels} out_vertices={out_vertices} \
         median_s={median_s:.6} mvps={:.3}",
        out_vertices as f64 / median_s / 1e6
    );
}

pub fn write_dump(path: &str, positions: &[[f64; 3]], faces: &[[u32; 4]]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| format!("{path}: {e}"))?;
    let mut w = BufWriter::with_capacity(1 << 20, file);
    let mut put = |b: &[u8]| w.write_all(b).map_err(|e| format!("{path}: {e}"));
    put(b"LSPEERS1")?;
    put(&(positions.len() as u64).to_le_bytes())?;
    put(&(faces.len() as u64).to_le_bytes())?;
    for p in positions {
        for c in p {
            put(&c.to_le_bytes())?;
        }
    }
    for f in faces {
        for i in f {
            put(&i.to_le_bytes())?;
        }
    }
    w.flush().map_err(|e| format!("{path}: {e}"))
}

pub fn read_dump(path: &str) -> Result<Obj, String> {
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .map_err(|e| format!("{path}: {e}"))?;
    if bytes.len() < 24 || &bytes[..8] != b"LSPEERS1" {
        return Err(format!("{path}: not a dump file"));
    }
    let u64_at = |i: usize| u64::from_le_bytes(bytes[i..i + 8].try_into().unwrap()) as usize;
    let (nv, nf) = (u64_at(8), u64_at(16));
    if bytes.len() != 24 + nv * 24 + nf * 16 {
        return Err(format!("{path}: truncated dump"));
    }
    let f64_at = |i: usize| f64::from_le_bytes(bytes[i..i + 8].try_into().unwrap());
    let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap());
    let positions = (0..nv)
        .map(|v| std::array::from_fn(|c| f64_at(24 + v * 24 + c * 8)))
        .collect();
    let base = 24 + nv * 24;
    let faces = (0..nf)
        .map(|f| std::array::from_fn(|c| u32_at(base + f * 16 + c * 4)))
        .collect();
    Ok(Obj { positions, faces })
}

/// Runs `main_inner`, printing an error and exiting 1 on failure.
pub fn run(main_inner: fn(&[String]) -> Result<(), String>) {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Err(e) = main_inner(&args) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
