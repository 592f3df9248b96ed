//! The machine's own f32 / f64 ratio on the torus's work, as a yardstick for the f32 target:
//! a minimal kernel of the same shape as the composed patches (`patch/composed.rs`), in f64
//! and in f32, timed in the same run.
//!
//! Per face of the closed 256 × 256 torus: gather its 4 × 4 start points, refine them along x
//! and then y by the composed matrix of three uniform cubic B-spline steps (N' = 8), and write
//! the 8 × 8 points it owns as one block of whole lines with non-temporal stores (a face-block
//! numbering: no shared edges or corners, no bookkeeping). 4,194,304 points, as
//! `lsubdiv bench` makes on this torus. What the kernel leaves out is exactly what it costs
//! lsubdiv to number the output the way meshes need it.
//!
//! `cargo bench --bench yardstick`

use std::hint::black_box;
use std::time::Instant;

/// Points of a face's final row that it owns, and faces of the torus along each side.
const N: usize = 8;
const SIDE: usize = 256;
/// Values of a row of owned points (interleaved xyz).
const ROW: usize = 3 * N;

/// The position scalar.
trait Scalar: Copy + Default + Send + Sync {
    fn of(x: f64) -> Self;
    fn madd(self, b: Self, c: Self) -> Self;
}

impl Scalar for f64 {
    fn of(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn madd(self, b: Self, c: Self) -> Self {
        self.mul_add(b, c)
    }
}

impl Scalar for f32 {
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn madd(self, b: Self, c: Self) -> Self {
        self.mul_add(b, c)
    }
}

/// One step of uniform cubic B-spline subdivision of a row of k points (ring included): the
/// 2k − 3 new points it determines, edge and vertex points in turn (edge 0–1, vertex 1, …,
/// edge (k − 2)–(k − 1)).
fn step(old: &[[f64; 4]]) -> Vec<[f64; 4]> {
    let edge =
        |i: usize| -> [f64; 4] { std::array::from_fn(|k| (old[i][k] + old[i + 1][k]) / 2.0) };
    let vertex = |i: usize| -> [f64; 4] {
        std::array::from_fn(|k| (old[i - 1][k] + 6.0 * old[i][k] + old[i + 1][k]) / 8.0)
    };
    let mut new = vec![edge(0)];
    for i in 1..old.len() - 1 {
        new.push(vertex(i));
        new.push(edge(i));
    }
    new
}

/// M: rows x' = 0..N of a face's final points, each its weights on the 4 start points
/// (x = −1..=2), from three steps applied to the unit rows (dyadic weights, exact in f64).
fn composed() -> [[f64; 4]; N] {
    let mut row: Vec<[f64; 4]> = (0..4)
        .map(|i| std::array::from_fn(|k| f64::from(u8::from(i == k))))
        .collect();
    // Each step keeps one point of ring: 4 → 5 → 7 → 11 points, x' = −1..=9 at the end.
    for _ in 0..3 {
        row = step(&row);
    }
    std::array::from_fn(|x| row[x + 1])
}

/// Per face, its 16 start points (rows y − 1..=y + 2, columns x − 1..=x + 2, wrapped).
fn gather_table() -> Vec<[u32; 16]> {
    let at = |r: usize, c: usize| ((r % SIDE) * SIDE + c % SIDE) as u32;
    (0..SIDE * SIDE)
        .map(|f| {
            let (r, c) = (f / SIDE + SIDE, f % SIDE + SIDE);
            std::array::from_fn(|k| at(r + k / 4 - 1, c + k % 4 - 1))
        })
        .collect()
}

/// How a run writes: the lines alone (nothing computed: the write-only bound), the kernel
/// with each face's lines in one burst after its sums, or the kernel with each face's lines
/// spread over the next face's rows (a share after each row).
const ALONE: u8 = 0;
const BURST: u8 = 1;
const SPREAD: u8 = 2;

/// Lines of a face's block (1536 or 768 bytes).
const fn lines<T>() -> usize {
    3 * N * N * size_of::<T>() / 64
}

/// Per start point i, the weight of each value v = 3x' + c of a row refined along x.
fn columns<T: Scalar>(m: &[[T; 4]; N]) -> [[T; ROW]; 4] {
    std::array::from_fn(|i| std::array::from_fn(|v| m[v / 3][i]))
}

/// A start row of 4 points refined along x: weights per value, each point repeated along the
/// row. (Broadcast coordinates times weights zero off their coordinate, three FMAs a value,
/// measured slower.)
#[inline(always)]
fn along_x<T: Scalar>(columns: &[[T; ROW]; 4], points: [[T; 3]; 4]) -> [T; ROW] {
    let mut acc = [T::default(); ROW];
    for (column, p) in columns.iter().zip(points) {
        let mut r = [T::default(); ROW];
        for x in 0..N {
            r[3 * x..3 * x + 3].copy_from_slice(&p);
        }
        for v in 0..ROW {
            acc[v] = column[v].madd(r[v], acc[v]);
        }
    }
    acc
}

/// Two face blocks in turn: the face's, and the one before it, still being written when the
/// lines are spread.
struct Blocks<T>([Block<T>; 2]);

impl<T: Scalar> Blocks<T> {
    fn new() -> Self {
        Blocks([
            Block([T::default(); 3 * N * N]),
            Block([T::default(); 3 * N * N]),
        ])
    }

    /// Face f's block and face f − 1's.
    #[inline(always)]
    fn pair(&mut self, f: usize) -> (&mut Block<T>, &Block<T>) {
        let [a, b] = &mut self.0;
        if f.is_multiple_of(2) {
            (a, b)
        } else {
            (b, a)
        }
    }

    /// Face f's rows along y from its 4 refined start rows into its block; its lines out
    /// after them (`BURST`), or face f − 1's a share after each row (`SPREAD`).
    #[inline(always)]
    fn along_y<const WIDE: bool, const MODE: u8>(
        &mut self,
        f: usize,
        m: &[[T; 4]; N],
        rows: &[[T; ROW]],
        out: &mut [T],
    ) {
        let lines = lines::<T>();
        let (this, last) = self.pair(f);
        for (y, weights) in m.iter().enumerate() {
            let mut acc = [T::default(); ROW];
            for (w, row) in weights.iter().zip(rows) {
                for v in 0..ROW {
                    acc[v] = w.madd(row[v], acc[v]);
                }
            }
            this.0[y * ROW..][..ROW].copy_from_slice(&acc);
            if MODE == SPREAD && f > 0 {
                let share = y * lines / N..(y + 1) * lines / N;
                write::<T, WIDE>(last, &mut out[block(f - 1)..], share);
            }
        }
        if MODE == BURST {
            write::<T, WIDE>(this, &mut out[block(f)..], 0..lines);
        }
    }

    /// After the last face (`count` faces), the lines still to write (`SPREAD`).
    #[inline(always)]
    fn finish<const WIDE: bool, const MODE: u8>(&self, count: usize, out: &mut [T]) {
        if MODE == SPREAD && count > 0 {
            let f = count - 1;
            write::<T, WIDE>(&self.0[f % 2], &mut out[block(f)..], 0..lines::<T>());
        }
    }
}

/// Face (or block) f's first value in the output.
const fn block(f: usize) -> usize {
    f * 3 * N * N
}

/// The kernel for every face: gather, along x, along y, the block out in whole lines (`MODE`).
#[inline(always)]
fn faces<T: Scalar, const WIDE: bool, const MODE: u8>(
    points: &[[T; 3]],
    table: &[[u32; 16]],
    m: &[[T; 4]; N],
    out: &mut [T],
) {
    let columns = columns(m);
    let mut blocks = Blocks::new();
    for (f, idx) in table.iter().enumerate() {
        if MODE == ALONE {
            write::<T, WIDE>(blocks.pair(f).0, &mut out[block(f)..], 0..lines::<T>());
            continue;
        }
        // Loops, not closures (`array::from_fn`, `array::map`): a closure does not take the
        // kernel's target features, and with them the stacked form ran 12–40 % slower.
        let mut rows = [[T::default(); ROW]; 4];
        for (j, row) in rows.iter_mut().enumerate() {
            let mut start = [[T::default(); 3]; 4];
            for (i, p) in start.iter_mut().enumerate() {
                *p = points[idx[4 * j + i] as usize];
            }
            *row = along_x(&columns, start);
        }
        blocks.along_y::<WIDE, MODE>(f, m, &rows, out);
    }
    blocks.finish::<WIDE, MODE>(table.len(), out);
}

/// The kernel as lsubdiv runs it on the torus: stacks of 16 faces along y sharing their start
/// rows, each start row refined along x once (19 rows for 16 faces), then each face's rows
/// along y; a face's block goes out in one burst or spread over the next face's rows (blocks
/// numbered in the order the faces are refined). Compiled for AVX-512F only.
#[inline(always)]
fn stacked<T: Scalar, const MODE: u8>(points: &[[T; 3]], m: &[[T; 4]; N], out: &mut [T]) {
    const STACK: usize = 16;
    let columns = columns(m);
    let mut blocks = Blocks::new();
    let mut f = 0;
    for c in 0..SIDE {
        for r0 in (0..SIDE).step_by(STACK) {
            let mut rows = [[T::default(); ROW]; STACK + 3];
            for (j, row) in rows.iter_mut().enumerate() {
                let r = (r0 + SIDE + j - 1) % SIDE;
                let mut start = [[T::default(); 3]; 4];
                for (i, p) in start.iter_mut().enumerate() {
                    *p = points[r * SIDE + (c + SIDE + i - 1) % SIDE];
                }
                *row = along_x(&columns, start);
            }
            for q in 0..STACK {
                blocks.along_y::<true, MODE>(f, m, &rows[q..q + 4], out);
                f += 1;
            }
        }
    }
    blocks.finish::<true, MODE>(f, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,fma")]
unsafe fn stacked_avx512<T: Scalar, const MODE: u8>(p: &[[T; 3]], m: &[[T; 4]; N], out: &mut [T]) {
    stacked::<T, MODE>(p, m, out);
}

/// One refinement of the torus by [`stacked`]: seconds (`None` without AVX-512F and FMA).
fn run_stacked<T: Scalar, const MODE: u8>(
    p: &[[T; 3]],
    m: &[[T; 4]; N],
    out: &mut [T],
) -> Option<f64> {
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("fma") {
        let t = Instant::now();
        // SAFETY: the CPU has AVX-512F and FMA (checked above); SSE2 is every x86-64's.
        unsafe {
            stacked_avx512::<T, MODE>(p, m, out);
            std::arch::x86_64::_mm_sfence();
        }
        black_box(&*out);
        return Some(t.elapsed().as_secs_f64());
    }
    let _ = (p, m, out);
    None
}

/// A face's block, at a 64-byte line.
#[repr(align(64))]
struct Block<T>([T; 3 * N * N]);

/// Writes lines `lines` of the block over the same lines of `dst` with non-temporal stores,
/// 64 bytes at a time where `WIDE` (AVX-512F, as lsubdiv's writers), else 16.
#[inline(always)]
fn write<T: Scalar, const WIDE: bool>(
    block: &Block<T>,
    dst: &mut [T],
    lines: std::ops::Range<usize>,
) {
    let per = 64 / size_of::<T>();
    let (s, d) = (
        &block.0[lines.start * per..lines.end * per],
        &mut dst[lines.start * per..],
    );
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        let (s, d) = (s.as_ptr(), d.as_mut_ptr());
        // SAFETY: both are 64-byte aligned (the block by its type, `dst` at a multiple of a
        // block's size from a 64-byte aligned buffer) and hold these lines; SSE2 is every
        // x86-64's, and `WIDE` is only set where the CPU has AVX-512F.
        unsafe {
            if WIDE {
                for k in 0..lines.len() {
                    let v = _mm512_load_si512(s.cast::<__m512i>().add(k));
                    _mm512_stream_si512(d.cast::<__m512i>().add(k), v);
                }
            } else {
                for k in 0..4 * lines.len() {
                    let v = _mm_load_si128(s.cast::<__m128i>().add(k));
                    _mm_stream_si128(d.cast::<__m128i>().add(k), v);
                }
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    d[..s.len()].copy_from_slice(s);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,fma")]
unsafe fn faces_avx512<T: Scalar, const MODE: u8>(
    p: &[[T; 3]],
    t: &[[u32; 16]],
    m: &[[T; 4]; N],
    out: &mut [T],
) {
    faces::<T, true, MODE>(p, t, m, out);
}

/// One refinement of the torus (or its lines written alone): seconds.
fn run<T: Scalar, const MODE: u8>(
    points: &[[T; 3]],
    table: &[[u32; 16]],
    m: &[[T; 4]; N],
    out: &mut [T],
) -> f64 {
    let t = Instant::now();
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx512f") && is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX-512F and FMA (checked above).
        unsafe { faces_avx512::<T, MODE>(points, table, m, out) };
    } else {
        faces::<T, false, MODE>(points, table, m, out);
    }
    #[cfg(not(target_arch = "x86_64"))]
    faces::<T, false, MODE>(points, table, m, out);
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE2 is every x86-64's.
    unsafe {
        std::arch::x86_64::_mm_sfence()
    };
    black_box(&*out);
    t.elapsed().as_secs_f64()
}

/// A buffer of `len` values starting at a 64-byte line.
fn aligned<T: Scalar>(storage: &mut Vec<T>, len: usize) -> &mut [T] {
    storage.resize(len + 64 / size_of::<T>(), T::default());
    let at = storage.as_ptr().align_offset(64);
    &mut storage[at..at + len]
}

fn main() {
    let m64 = composed();
    let sums: Vec<f64> = m64.iter().map(|r| r.iter().sum()).collect();
    assert!(
        sums.iter().all(|&s| s == 1.0),
        "rows of M sum to 1: {sums:?}"
    );
    let m32: [[f32; 4]; N] = m64.map(|r| r.map(f32::of));
    let table = gather_table();
    let torus = |r: usize, c: usize| {
        let (u, v) = (
            std::f64::consts::TAU * r as f64 / SIDE as f64,
            std::f64::consts::TAU * c as f64 / SIDE as f64,
        );
        [
            (2.0 + v.cos()) * u.cos(),
            (2.0 + v.cos()) * u.sin(),
            v.sin(),
        ]
    };
    let p64: Vec<[f64; 3]> = (0..SIDE * SIDE)
        .map(|i| torus(i / SIDE, i % SIDE))
        .collect();
    let p32: Vec<[f32; 3]> = p64.iter().map(|p| p.map(f32::of)).collect();
    let len = SIDE * SIDE * 3 * N * N;
    let (mut s64, mut s32) = (Vec::new(), Vec::new());
    let (o64, o32) = (aligned::<f64>(&mut s64, len), aligned::<f32>(&mut s32, len));
    // One warm-up each (the pages), then alternated, median of 9.
    run::<_, BURST>(&p64, &table, &m64, o64);
    run::<_, BURST>(&p32, &table, &m32, o32);
    let mut t: [Vec<f64>; 6] = Default::default();
    for _ in 0..9 {
        t[0].push(run::<_, ALONE>(&p64, &table, &m64, o64));
        t[1].push(run::<_, ALONE>(&p32, &table, &m32, o32));
        t[2].push(run::<_, SPREAD>(&p64, &table, &m64, o64));
        t[3].push(run::<_, SPREAD>(&p32, &table, &m32, o32));
        t[4].push(run::<_, BURST>(&p64, &table, &m64, o64));
        t[5].push(run::<_, BURST>(&p32, &table, &m32, o32));
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let t = t.map(median);
    let points = (SIDE * SIDE * N * N) as f64;
    // The same points in both: f32 agrees with f64 to its rounding.
    let worst = o64
        .iter()
        .zip(o32.iter())
        .map(|(a, b)| (a - f64::from(*b)).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-5, "f32 and f64 kernels agree: {worst:e}");
    println!(
        "Minimal per-face kernel, closed 256 × 256 torus, {} points (N' = 8, face blocks, non-temporal lines), 1 thread, M points/s:",
        points as usize
    );
    for (what, k) in [
        ("lines alone (nothing computed)", 0),
        ("kernel, a face's lines in one burst after its sums", 4),
        ("kernel, a face's lines spread over the next face's rows", 2),
    ] {
        println!(
            "{what}: f64 {:.1}, f32 {:.1}, f32 / f64 = {:.2}×",
            points / t[k] / 1e6,
            points / t[k + 1] / 1e6,
            t[k] / t[k + 1]
        );
    }
    // The same as lsubdiv runs it: stacks of faces sharing their start rows.
    let mut u: [Vec<f64>; 4] = Default::default();
    for _ in 0..9 {
        let runs = [
            run_stacked::<_, BURST>(&p64, &m64, o64),
            run_stacked::<_, BURST>(&p32, &m32, o32),
            run_stacked::<_, SPREAD>(&p64, &m64, o64),
            run_stacked::<_, SPREAD>(&p32, &m32, o32),
        ];
        for (u, r) in u.iter_mut().zip(runs.into_iter().flatten()) {
            u.push(r);
        }
    }
    if u[0].is_empty() {
        println!("stacked: needs AVX-512F and FMA");
    } else {
        let u = u.map(median);
        println!(
            "stacked (16 faces sharing their start rows, as lsubdiv): burst f64 {:.1}, f32 {:.1}; spread f64 {:.1}, f32 {:.1}",
            points / u[0] / 1e6,
            points / u[1] / 1e6,
            points / u[2] / 1e6,
            points / u[3] / 1e6
        );
    }
    println!(
        "spread / burst: f64 {:.2}×, f32 {:.2}×",
        t[4] / t[2],
        t[5] / t[3]
    );
}
