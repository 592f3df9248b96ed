//! Composed patches: every depth-first step of an ordinary face at once.
//!
//! The steps of a face whose corners are all ordinary apply the same 1D plans along both axes
//! (every face's rows and columns are labelled by the same W_s, \[G\] Cor. 4.4), and a step
//! refines the patch's ring with it. So the s plans compose into one matrix M = P_s ⋯ P_1
//! from the start row with its ring (side m = N₀ + 3) to the final points 0..=N', and the
//! face's final patch is the tensor product M · P · Mᵀ of its start patch P (\[G\] §2.2: the
//! bivariate scheme is the tensor product of the univariate one on regular regions). Phantoms
//! are set in P once: refining keeps them phantoms. M is multiplied out in f64 from the emitted
//! masks; rows are banded (at most d + 1 start points reach a final point, Boehm's knot
//! insertion), and every row sums to 1 to rounding, as the masks do.
//!
//! The kernel is two passes of broadcast weights and per-lane weights over rows of points
//! kept interleaved (x y z x y z …), so that a refined row comes out in the output's order:
//! - along x, each start row i: `A[i][v] = Σ_j Mx[j][v] · P[i][j][c(v)]`, v = 3x' + c, with
//!   the weights of column j laid out per value (`Mx[j][v] = M[x'][j]`) and the point P[i][j]
//!   repeated in the lanes' coordinate pattern;
//! - along y, each final row y': `Q[y'] = Σ_i M[y'][i] · A[i]`, a sum of whole rows.
//!
//! Faces that follow each other along y (each one's edge 2 the next one's edge 0) share their
//! start rows: a stack of s faces has s·N₀ + 3 start rows, each refined along x once, and face
//! q's final rows are the sums over its own start rows, q·N₀ up. The products and their order
//! are those of each face alone, so a stack gives the same bits.
//!
//! A face's final rows go to its writer together, in bands of at most [`BAND`] values
//! ([`Rows`]): it takes its corners and edges from them, and its interior (points 1..N' − 1
//! of rows 1..N' − 1) as one run that the sums store a second time as they go, row after
//! row. Of those rows only the tiles of points 0 and N' stay in the rows, and of point 0 only
//! where the face wants it ([`Faces::wants_left`]). Before, the interior was packed from the
//! rows afterwards: storing it as it is summed made the torus 7–27 % faster
//! (the history of docs/benchmarks.md).
//!
//! Both are written on tiles of 32 values that the compiler turns into vectors: the kernel
//! is compiled for AVX-512, AVX2 (both with fused multiply-add) and the baseline, chosen at
//! run time ([`Simd`]). The operations and their order are the same on every path; the FMA
//! paths round each product-and-sum once, so they differ from the baseline by rounding only
//! (and AVX2 and AVX-512 give the same bits). Where a face's final rows all sum the same four
//! start rows (cubic schemes refined from their first step), the AVX-512 and AVX2 paths sum
//! a band's rows tile by tile in one tight loop with those rows' tile (or part of it) held in
//! vector registers ([`tight_sums`]): the same operations in the same order.

#[cfg(target_arch = "x86_64")]
use super::stream::lanes_avx2;
use super::Simd;
use crate::real::Real;

/// The composed 1D matrix of a chunk of depth-first steps, laid out for the kernel.
pub(super) struct Composed<T> {
    /// Start side with its ring, N₀ + 3.
    m: usize,
    /// Values of a refined row, padded to whole tiles.
    width: usize,
    /// Per final point y' = 0..=N': its first start point.
    first: Vec<usize>,
    /// Per final point: its weights on the `band` start points from its first (zero-padded).
    weights: Vec<T>,
    band: usize,
    /// Per start point j: `width` weights, M[x'][j] at every value v = 3x' + c (at PAD + v).
    columns: Vec<T>,
    /// Per start point j: the values v its column reaches (nonzero weights).
    reach: Vec<std::ops::Range<usize>>,
    /// Faces in a stack at most: [`STACK`] start rows, so that the scratch stays within a
    /// few final patches whatever N₀ (`patch::footprint`).
    most: usize,
    /// A face's final rows handed at once at most ([`BAND`] values, at least one row).
    rows: usize,
}

/// Values of a face's final rows handed to [`Faces::face`] at once at most (32 KiB of f64, so
/// that they are read back from the first-level cache).
const BAND: usize = 4096;

/// Start rows a face's final rows sum in [`tight_sums`].
const BLOCK: usize = 4;

/// Start rows (less the ring) of a stack of faces at most (`Composed::most`).
const STACK: usize = 16;

/// Values the kernel sums at once: its independent accumulators (four AVX-512 vectors of f64,
/// eight AVX2 ones), so that the sums' latency overlaps.
const TILE: usize = 32;

/// Values before a refined row's point 0, so that its point 1 starts a vector of 8 values: a
/// row's interior is then summed in whole vectors, and the 8 values before it only where
/// its point 0 is wanted (f64, [`skips`]).
const PAD: usize = 5;

/// Values of a refined row before its point 1 (a multiple of 8, [`PAD`]).
const LEAD: usize = PAD + 3;

/// Bytes of a cache line, and of an AVX-512 vector.
const LINE: usize = 64;

/// Whether the values before point 1 are a whole vector (f64), so that a row summed from point
/// 1 on loads and stores whole aligned vectors; for f32 they are half a vector, and every
/// vector from point 1 on would straddle two lines.
const fn skips<T>() -> bool {
    (LEAD * size_of::<T>()).is_multiple_of(LINE)
}

impl<T: Real> Composed<T> {
    /// Lays out M (rows 0..=N', each `m` weights).
    pub(super) fn new(m: usize, matrix: &[Vec<f64>]) -> Composed<T> {
        let values = matrix.len() * 3;
        let width = (PAD + values).div_ceil(TILE) * TILE;
        let mut columns = vec![T::default(); m * width];
        let mut reach = vec![0..0; m];
        for (j, reach) in reach.iter_mut().enumerate() {
            let col = &mut columns[j * width..][..width];
            let mut vs = (0..values).filter(|&v| matrix[v / 3][j] != 0.0);
            let first = vs.next().unwrap_or(0);
            let last = vs.next_back().unwrap_or(first);
            for (v, w) in col[PAD..].iter_mut().enumerate().take(values) {
                *w = T::from_f64(matrix[v / 3][j]);
            }
            *reach = PAD + first..PAD + last + 1;
        }
        // Each row's nonzero weights, as a band of one width starting where the row's do (or
        // earlier, at the end of the start row).
        let spans: Vec<(usize, usize)> = matrix
            .iter()
            .map(|r| {
                let lo = r.iter().position(|&w| w != 0.0).unwrap_or(0);
                let hi = r.iter().rposition(|&w| w != 0.0).map_or(lo, |h| h + 1);
                (lo, hi)
            })
            .collect();
        let band = spans.iter().map(|&(lo, hi)| hi - lo).max().unwrap_or(0);
        let first: Vec<usize> = spans.iter().map(|&(lo, _)| lo.min(m - band)).collect();
        let weights = matrix
            .iter()
            .zip(&first)
            .flat_map(|(r, &lo)| r[lo..lo + band].iter().map(|&w| T::from_f64(w)))
            .collect();
        Composed {
            m,
            width,
            first,
            weights,
            band,
            columns,
            reach,
            most: (STACK / (m - 3)).max(1),
            rows: (BAND / width).clamp(1, matrix.len()),
        }
    }

    /// Whether its refined rows fill at least three quarters of their tiles (the kernel sums
    /// whole tiles of [`TILE`] values).
    pub(super) fn fills_tiles(&self) -> bool {
        4 * (PAD + 3 * self.first.len()) >= 3 * self.width
    }

    /// Scratch values a stack of faces needs: the start patch, the rows refined along x, a
    /// face's final rows and the row it shares with the next face.
    pub(super) fn scratch_len(&self) -> usize {
        let rows = self.rows(self.most);
        LINE / size_of::<T>() + self.patch_len(self.m) + (rows + 2 * self.rows + 2) * self.width
    }

    /// Values of a stack's start patch, in whole tiles (so that the rows after it start at
    /// 64-byte lines, as the scratch does).
    fn patch_len(&self, m: usize) -> usize {
        (self.rows(self.most) * m * 3).next_multiple_of(TILE)
    }

    /// Refines `faces.count()` faces one after the other with the vectors of `simd`: each
    /// start patch is loaded by [`Faces::load`] (rows y = −1..=N₀+1 of m points each,
    /// interleaved, at the front of `scratch`), and each face's final rows y' = 0..=N'
    /// handed to [`Faces::face`], interleaved, a band of rows at a time. The whole loop,
    /// `faces`' methods inlined, is compiled for the path.
    #[inline(always)]
    pub(super) fn run(&self, simd: Simd, scratch: &mut [T], faces: &mut impl Faces<T>) {
        // Rows at 64-byte lines: no vector load or store of a tile straddles two.
        let at = scratch
            .as_ptr()
            .align_offset(LINE)
            .min(LINE / size_of::<T>());
        let scratch = &mut scratch[at..];
        match simd {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Simd::Avx512` is only handed out where the CPU has AVX-512F.
            Simd::Avx512 => unsafe { self.run_avx512(scratch, faces) },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Simd::Avx2` is only handed out where the CPU has AVX2 and FMA.
            Simd::Avx2 => unsafe { self.run_avx2(scratch, faces) },
            _ => self.run_any::<false, false>(scratch, faces),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,fma")]
    unsafe fn run_avx512(&self, scratch: &mut [T], faces: &mut impl Faces<T>) {
        self.run_any::<true, true>(scratch, faces);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_avx2(&self, scratch: &mut [T], faces: &mut impl Faces<T>) {
        self.run_any::<true, false>(scratch, faces);
    }

    /// The face loop, its sizes made constants where they are the common ones
    /// ([`Sizes`]) so that the compiler unrolls the loops over them; `FUSED`: AVX2 and FMA
    /// are there, `WIDE`: AVX-512F too ([`tight_sums`]).
    #[inline(always)]
    fn run_any<const FUSED: bool, const WIDE: bool>(
        &self,
        scratch: &mut [T],
        faces: &mut impl Faces<T>,
    ) {
        let sizes = Sizes::new(self.m, self.band, self.width);
        match (sizes.m, sizes.band, sizes.width) {
            (4, 4, 32) => self.faces::<FUSED, WIDE>(Sizes::new(4, 4, 32), scratch, faces),
            _ => self.faces::<FUSED, WIDE>(sizes, scratch, faces),
        }
    }

    #[inline(always)]
    fn faces<const FUSED: bool, const WIDE: bool>(
        &self,
        sizes: Sizes,
        scratch: &mut [T],
        faces: &mut impl Faces<T>,
    ) {
        let mut i = 0;
        while i < faces.count() {
            let patch = &mut scratch[..self.patch_len(sizes.m)];
            let stack = faces.load(i, self.most, patch);
            self.refine::<FUSED, WIDE>(sizes, stack, scratch, faces);
            i += stack;
        }
    }

    /// Start rows of a stack of `stack` faces with its ring.
    fn rows(&self, stack: usize) -> usize {
        stack * (self.m - 3) + 3
    }

    /// A stack of faces (each one's edge 2 the next one's edge 0, in the same direction):
    /// its start patch at the front of `scratch` (rows y = −1..=s·N₀+1) to its faces' final
    /// rows, handed to `faces` face by face; `FUSED`: each product is added with one rounding
    /// (FMA). The faces share their start rows, so each is refined along x once; face q's
    /// final row y is from its own start rows, q·N₀ up, and its row 0 is face q − 1's row N'.
    #[inline(always)]
    fn refine<const FUSED: bool, const WIDE: bool>(
        &self,
        sizes: Sizes,
        stack: usize,
        scratch: &mut [T],
        faces: &mut impl Faces<T>,
    ) {
        let Sizes { m, band, width } = sizes;
        let (n0, n) = (m - 3, self.first.len() - 1);
        let rows = self.rows(stack);
        let (p, rest) = scratch.split_at_mut(self.patch_len(m));
        let (a, rest) = rest.split_at_mut(self.rows(self.most) * width);
        let (out, rest) = rest.split_at_mut(self.rows * width);
        let (top, inside) = rest.split_at_mut(width);
        // The band's points 1..N' − 1 of rows 1..N' − 1, row after row (`len` values each),
        // stored as they are summed (each row's tiles run on past them, over the next row's
        // start, which is stored after them).
        let len = (n - 1) * 3;
        let inside = &mut inside[..(self.rows + 1) * width];
        // The tiles of point N'.
        let last = (PAD + 3 * n) / TILE..=(PAD + 3 * n + 2) / TILE;
        // Along x: each start row into a refined row of N' + 1 points.
        for (pi, ai) in p[..rows * m * 3]
            .chunks_exact(m * 3)
            .zip(a.chunks_exact_mut(width))
        {
            for (q, out) in ai.chunks_exact_mut(TILE).enumerate() {
                let v0 = q * TILE;
                let mut acc = [T::default(); TILE];
                for (j, reach) in self.reach[..m].iter().enumerate() {
                    if reach.end <= v0 || v0 + TILE <= reach.start {
                        continue;
                    }
                    let w: &[T; TILE] = tile(&self.columns[j * width + v0..]);
                    let r = repeated(&pi[j * 3..j * 3 + 3], (v0 + 3 - PAD % 3) % 3);
                    for l in 0..TILE {
                        acc[l] = madd::<T, FUSED>(w[l], r[l], acc[l]);
                    }
                }
                out.copy_from_slice(&acc);
            }
        }
        // Along y: each final row, a sum of whole refined rows, in bands of `self.rows`. Rows
        // 0 and N' only where wanted; row 0 of a face after the first is the row N' before
        // it, kept in `top`.
        // On AVX-512 and AVX2, where every final row sums the same start rows (band = m = 4:
        // cubic schemes refined from the first step), a band's rows are summed tile by tile
        // in one tight loop ([`tight_sums`]).
        let tight = FUSED && band == m && m == BLOCK;
        for q in 0..stack {
            // (Only the row-by-row sums ask.)
            let left = !tight && faces.wants_left(q);
            for y0 in (0..=n).step_by(self.rows) {
                let ys = y0..(y0 + self.rows).min(n + 1);
                let first = inner_rows(&ys, n).start;
                if tight {
                    let rows = &a[q * n0 * width..][..BLOCK * width];
                    // Last tile first: a row's last interior tile runs on into the next row's
                    // first ones, stored after it.
                    for t in (0..width / TILE).rev() {
                        let band = Band {
                            ys: ys.clone(),
                            n,
                            width,
                            len,
                            tile: t,
                            ends: t == 0 || last.contains(&t),
                        };
                        // SAFETY: `FUSED` is only set on the paths compiled for AVX2 and FMA,
                        // and `WIDE` on the one compiled for AVX-512F.
                        unsafe { tight_sums::<T, WIDE>(rows, &self.weights, out, inside, band) };
                    }
                    if q > 0 && y0 == 0 {
                        out[..width].copy_from_slice(top);
                    }
                }
                // Else row by row, each only where wanted.
                for y in if tight { 0..0 } else { ys.clone() } {
                    let row = &mut out[(y - y0) * width..][..width];
                    let wanted = match y {
                        0 if q > 0 => {
                            row.copy_from_slice(top);
                            continue;
                        }
                        0 => faces.wants(q, 0),
                        y if y == n => {
                            faces.wants(q, n) || (q + 1 < stack && faces.wants(q + 1, 0))
                        }
                        _ => true,
                    };
                    if !wanted {
                        continue;
                    }
                    let ws = &self.weights[y * band..][..band];
                    let a = &a[(q * n0 + self.first[y]) * width..];
                    // The values before point 1 only where point 0 is wanted.
                    let lead = y == 0 || y == n || left || !skips::<T>();
                    let inner = (y != 0 && y != n).then(|| (y - first) * len);
                    for t in 0..width / TILE {
                        // An inner row keeps in `out` only its tiles of points 0 and N'.
                        let edge = (t == 0 && lead) || last.contains(&t);
                        let row = (inner.is_none() || edge).then_some(&mut *row);
                        let inside = inner.map(|i| &mut inside[i..]);
                        match t {
                            0 if lead => sum::<T, TILE, LEAD, FUSED>(ws, a, width, 0, row, inside),
                            0 => {
                                sum::<T, { TILE - LEAD }, 0, FUSED>(ws, a, width, LEAD, row, inside)
                            }
                            _ => sum::<T, TILE, 0, FUSED>(ws, a, width, t * TILE, row, inside),
                        }
                    }
                }
                if ys.end == n + 1 && q + 1 < stack {
                    top.copy_from_slice(&out[(n - y0) * width..][..width]);
                }
                faces.face(
                    q,
                    Rows {
                        values: &out[..ys.len() * width],
                        inside,
                        width,
                        n,
                        ys,
                    },
                );
            }
        }
    }
}

/// A band of a face's final rows `ys` (rows 0 and N' only if wanted, [`Faces::wants`]), each
/// `width` values: its points interleaved from [`PAD`] on, then the rest of its tiles.
pub(super) struct Rows<'a, T> {
    values: &'a [T],
    /// Points 1..N' − 1 of the band's rows 1..N' − 1, row after row (and then values past
    /// them).
    inside: &'a [T],
    width: usize,
    /// The face's last row, N'.
    n: usize,
    ys: std::ops::Range<usize>,
}

impl<T: Copy> Rows<'_, T> {
    /// The rows' y.
    pub(super) fn ys(&self) -> std::ops::Range<usize> {
        self.ys.clone()
    }

    /// The rows' y that are inner rows, 1..N' − 1 (their interior is in [`Rows::inside`]).
    #[inline(always)]
    pub(super) fn inner(&self) -> std::ops::Range<usize> {
        inner_rows(&self.ys, self.n)
    }

    /// Row y's points, interleaved, then the rest of the row's tiles. Of a row 1..N' − 1 only
    /// points 0 (if [`Faces::wants_left`]) and N' are set: its interior is in
    /// [`Rows::inside`].
    #[inline(always)]
    pub(super) fn row(&self, y: usize) -> &[T] {
        let i = y - self.ys.start;
        &self.values[i * self.width + PAD..(i + 1) * self.width]
    }

    /// Points 1..N' − 1 of the band's rows 1..N' − 1, one row after the other.
    #[inline(always)]
    pub(super) fn inside(&self) -> &[T] {
        &self.inside[..self.inner().len() * 3 * (self.n - 1)]
    }
}

/// The sizes the kernel's loops run over: start side, band, values of a refined row.
#[derive(Clone, Copy)]
struct Sizes {
    m: usize,
    band: usize,
    width: usize,
}

impl Sizes {
    #[inline(always)]
    const fn new(m: usize, band: usize, width: usize) -> Sizes {
        Sizes { m, band, width }
    }
}

/// The faces [`Composed::run`] refines, and where their points go.
pub(super) trait Faces<T> {
    /// How many.
    fn count(&self) -> usize;
    /// Loads the start patch of a stack of faces from the i-th on, at most `stack` of them
    /// (`Composed::most`), and says how many: face i + q + 1's edge 0 is face i + q's
    /// edge 2, in the same direction, and no phantom is set (each face's ring is its
    /// neighbours' points).
    fn load(&mut self, i: usize, stack: usize, patch: &mut [T]) -> usize;
    /// Whether face q of the stack loaded last wants its final row y, 0 or N' (else it is
    /// not computed, unless the face next to it along y wants it).
    fn wants(&self, q: usize, y: usize) -> bool;
    /// Whether face q of the stack loaded last wants point 0 of its rows 1..N' − 1 (its
    /// edge 3; else those points are not computed).
    fn wants_left(&self, q: usize) -> bool;
    /// Takes a band of face q's final rows (faces in order, each face's bands in order).
    fn face(&mut self, q: usize, rows: Rows<'_, T>);
}

/// Sums `L` values of a final row from `at` on: `out[v] = Σ_i ws[i] · a[i · width + v]`, in
/// increasing i (the same order whatever `L`, so a part of a tile has the tile's bits); the
/// values from point 1 on (`SKIP` values after `at`) also go to `inside`, from its start.
#[inline(always)]
fn sum<T: Real, const L: usize, const SKIP: usize, const FUSED: bool>(
    ws: &[T],
    a: &[T],
    width: usize,
    at: usize,
    out: Option<&mut [T]>,
    inside: Option<&mut [T]>,
) {
    let mut acc = [T::default(); L];
    // One bounds check for the band's rows, not one per row.
    let a = &a[at..][..(ws.len().max(1) - 1) * width + L];
    for (i, &w) in ws.iter().enumerate() {
        let s: &[T; L] = tile(&a[i * width..]);
        for l in 0..L {
            acc[l] = madd::<T, FUSED>(w, s[l], acc[l]);
        }
    }
    if let Some(out) = out {
        out[at..at + L].copy_from_slice(&acc);
    }
    if let Some(inside) = inside {
        inside[at + SKIP - LEAD..][..L - SKIP].copy_from_slice(&acc[SKIP..]);
    }
}

/// The rows of `ys` that are inner rows of a face's 0..=N', 1..N' − 1: the rows whose
/// interior goes to the writer as one run.
#[inline(always)]
fn inner_rows(ys: &std::ops::Range<usize>, n: usize) -> std::ops::Range<usize> {
    ys.start.max(1)..ys.end.min(n)
}

/// Tile `tile` of a band `ys` of a face's final rows (of 0..=N'), rows `width` values apart,
/// interiors `len` apart ([`tight_sums`]).
struct Band {
    ys: std::ops::Range<usize>,
    n: usize,
    width: usize,
    len: usize,
    tile: usize,
    /// The tile holds point 0 or N', which the writer takes from the rows (else only rows
    /// 0 and N' keep it there).
    ends: bool,
}

/// Tile `band.tile` of a face's final rows `band.ys` (`ws`: [`BLOCK`] weights per row y)
/// from the same tile of its [`BLOCK`] start rows `rows`: each row into `out` (the band's
/// rows) where it keeps the tile there (`Band::ends`), and its values from point 1 on into
/// `inside` where the row is one of 1..N' − 1 and the tile holds interior points, as [`sum`]
/// makes them on the FMA paths (the same products in the same order, so the same bits). The
/// start rows' part of the tile is held in vector registers (all of it with AVX-512, parts
/// of 8 f64 or 16 f32 values with AVX2's 16 registers) and the loop has nothing else in it:
/// summed row by row among the wanted-row tests, the compiler reloads them for every row
/// and splits an f32 tile into 8 + 16 + 8 lanes (AVX-512, torus 256 × 256: f32 +16–18 %,
/// Fibonacci f32 +20 %, Binary-Ternary +8 %, uniform binary f64 within noise; torus 64 × 64,
/// four tiles a row: f64 +14 %, f32 +50 %; the history of docs/benchmarks.md).
///
/// # Safety
/// The CPU has AVX-512F where `WIDE`, else AVX2 and FMA.
#[inline(always)]
unsafe fn tight_sums<T: Real, const WIDE: bool>(
    rows: &[T],
    ws: &[T],
    out: &mut [T],
    inside: &mut [T],
    band: Band,
) {
    let Band {
        ref ys,
        n,
        width,
        len,
        tile,
        ..
    } = band;
    let inner = inner_rows(ys, n);
    assert!(rows.len() >= (BLOCK - 1) * width + (tile + 1) * TILE);
    assert!(ws.len() >= ys.end * BLOCK && out.len() >= (ys.len() - 1) * width + (tile + 1) * TILE);
    assert!(inside.len() >= inner.len() * len + (tile + 1) * TILE);
    #[cfg(target_arch = "x86_64")]
    // SAFETY: the instruction sets (the caller's contract); every load and store is within
    // the slices (checked above). T is f64 or f32 (`Real`), told apart by its size.
    unsafe {
        use std::arch::x86_64::{__m256, __m256d, __m512, __m512d};
        let (r, w) = (rows.as_ptr().add(tile * TILE), ws.as_ptr());
        let (o, i) = (out.as_mut_ptr().add(tile * TILE), inside.as_mut_ptr());
        match (WIDE, size_of::<T>() == 8) {
            (true, true) => tight_rows::<__m512d>(r.cast(), w.cast(), o.cast(), i.cast(), band),
            (true, false) => tight_rows::<__m512>(r.cast(), w.cast(), o.cast(), i.cast(), band),
            (false, true) => tight_rows::<__m256d>(r.cast(), w.cast(), o.cast(), i.cast(), band),
            (false, false) => tight_rows::<__m256>(r.cast(), w.cast(), o.cast(), i.cast(), band),
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    unreachable!(
        "AVX-512 and AVX2 are x86-64's: {:?}",
        (rows.len(), ws.len(), out.len(), inside.len(), band.tile)
    );
}

/// [`tight_sums`] in vectors `V`: `rows` and `out` at the tile. The tile's parts go last first, as
/// the tiles do: a row's interior runs on into the next row's start, stored after it.
///
/// # Safety
/// As [`tight_sums`], its slices' bounds checked.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn tight_rows<V: Lanes>(
    rows: *const V::S,
    ws: *const V::S,
    out: *mut V::S,
    inside: *mut V::S,
    band: Band,
) {
    let Band {
        ys,
        n,
        width,
        len,
        tile,
        ends,
    } = band;
    let part = V::VECS * V::PER;
    // SAFETY: the caller's.
    unsafe {
        for p0 in (0..TILE).step_by(part).rev() {
            // The part's values from point 1 on: whether it holds any (the values before
            // point 1, `LEAD`, are not in a row's interior).
            let at = tile * TILE + p0;
            let holds = at + part > LEAD && at < LEAD + len;
            let mut r = [[V::zero(); 4]; BLOCK];
            for (i, r) in r.iter_mut().enumerate() {
                *r = load_row::<V>(rows.add(i * width + p0));
            }
            // Rows 0 and N' (where the band has them) into the rows; rows 1..N' − 1 into the
            // rows where they keep this tile there, and into the interior where it holds
            // some of it, one row `width` and `len` values after the other.
            for (has, y) in [(ys.start == 0, 0), (ys.end == n + 1, n)] {
                if has {
                    let acc = row_sums::<V>(&r, ws.add(y * BLOCK));
                    store_row::<V>(out.add((y - ys.start) * width + p0), &acc);
                }
            }
            let inner = inner_rows(&ys, n);
            let mut o = out.add((inner.start - ys.start) * width + p0);
            // Value v of a row goes to `d + v` (v ≥ LEAD).
            let mut d = inside.wrapping_sub(LEAD);
            for y in inner {
                let acc = row_sums::<V>(&r, ws.add(y * BLOCK));
                if ends {
                    store_row::<V>(o, &acc);
                }
                if holds {
                    for (k, a) in acc.iter().enumerate().take(V::VECS) {
                        // (Told apart by the part alone, so that the branches are decided
                        // when the loop over the parts is unrolled.)
                        let v = p0 + V::PER * k;
                        if tile > 0 || v >= LEAD {
                            V::store(d.add(at + V::PER * k), *a);
                        } else if v + V::PER > LEAD {
                            V::store_past(d.wrapping_add(v), *a, LEAD - v);
                        }
                    }
                }
                o = o.add(width);
                d = d.wrapping_add(len);
            }
        }
    }
}

/// A final row's part of a tile: `Σ_i ws[i] · r[i]` over the [`BLOCK`] start rows' part held
/// in `r`, in increasing i.
///
/// # Safety
/// The vectors' instruction set; `ws` holds [`BLOCK`] weights.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn row_sums<V: Lanes>(r: &[[V; 4]; BLOCK], ws: *const V::S) -> [V; 4] {
    // SAFETY: the caller's.
    unsafe {
        let mut acc = [V::zero(); 4];
        for (i, r) in r.iter().enumerate() {
            let w = V::splat(*ws.add(i));
            for (a, v) in acc.iter_mut().zip(r).take(V::VECS) {
                *a = V::fmadd(w, *v, *a);
            }
        }
        acc
    }
}

/// Loads a row's part of a tile from `p`.
///
/// # Safety
/// The vectors' instruction set; `p` holds the part.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn load_row<V: Lanes>(p: *const V::S) -> [V; 4] {
    // SAFETY: the caller's.
    unsafe {
        let mut acc = [V::zero(); 4];
        for (k, a) in acc.iter_mut().enumerate().take(V::VECS) {
            *a = V::load(p.add(V::PER * k));
        }
        acc
    }
}

/// Stores a row's part of a tile at `o`.
///
/// # Safety
/// The vectors' instruction set; `o` has room for the part.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn store_row<V: Lanes>(o: *mut V::S, acc: &[V; 4]) {
    for (k, a) in acc.iter().enumerate().take(V::VECS) {
        // SAFETY: the caller's.
        unsafe { V::store(o.add(V::PER * k), *a) };
    }
}

/// A vector of a scalar, for [`tight_rows`] (every method needs the vector's instruction set:
/// AVX-512F, or AVX2 and FMA).
#[cfg(target_arch = "x86_64")]
trait Lanes: Copy {
    /// The scalar.
    type S: Copy;
    /// Scalars in a vector.
    const PER: usize;
    /// Vectors a start row's part of a tile is held in (at most 4): four such rows, a row's
    /// sums and a weight in the registers there are.
    const VECS: usize;
    unsafe fn zero() -> Self;
    unsafe fn load(p: *const Self::S) -> Self;
    unsafe fn splat(x: Self::S) -> Self;
    unsafe fn fmadd(a: Self, b: Self, c: Self) -> Self;
    unsafe fn store(p: *mut Self::S, v: Self);
    /// Stores the lanes from `skip` on of `v` at `p` (lane l at `p + l`; those before `skip`
    /// are not written).
    unsafe fn store_past(p: *mut Self::S, v: Self, skip: usize);
}

/// The [`Lanes`] of a vector type: its scalar, lanes, vectors per part, and intrinsics
/// (zero, unaligned load, broadcast, fused multiply-add, unaligned store, masked store).
macro_rules! lanes {
    ($v:ident, $s:ty, $per:expr, $vecs:expr, $zero:ident, $load:ident, $splat:ident,
     $fmadd:ident, $store:ident, |$p:ident, $x:ident, $skip:ident| $past:expr) => {
        #[cfg(target_arch = "x86_64")]
        impl Lanes for std::arch::x86_64::$v {
            type S = $s;
            const PER: usize = $per;
            const VECS: usize = $vecs;
            #[inline(always)]
            unsafe fn zero() -> Self {
                unsafe { std::arch::x86_64::$zero() }
            }
            #[inline(always)]
            unsafe fn load(p: *const $s) -> Self {
                unsafe { std::arch::x86_64::$load(p) }
            }
            #[inline(always)]
            unsafe fn splat(x: $s) -> Self {
                unsafe { std::arch::x86_64::$splat(x) }
            }
            #[inline(always)]
            unsafe fn fmadd(a: Self, b: Self, c: Self) -> Self {
                unsafe { std::arch::x86_64::$fmadd(a, b, c) }
            }
            #[inline(always)]
            unsafe fn store(p: *mut $s, v: Self) {
                unsafe { std::arch::x86_64::$store(p, v) }
            }
            #[inline(always)]
            unsafe fn store_past($p: *mut $s, $x: Self, $skip: usize) {
                #[allow(unused_unsafe)]
                unsafe {
                    use std::arch::x86_64::*;
                    $past
                }
            }
        }
    };
}

lanes!(
    __m512d,
    f64,
    8,
    4,
    _mm512_setzero_pd,
    _mm512_loadu_pd,
    _mm512_set1_pd,
    _mm512_fmadd_pd,
    _mm512_storeu_pd,
    |p, v, skip| _mm512_mask_storeu_pd(p, (0xffu32 << skip) as u8, v)
);
lanes!(
    __m512,
    f32,
    16,
    2,
    _mm512_setzero_ps,
    _mm512_loadu_ps,
    _mm512_set1_ps,
    _mm512_fmadd_ps,
    _mm512_storeu_ps,
    |p, v, skip| _mm512_mask_storeu_ps(p, (0xffffu32 << skip) as u16, v)
);
lanes!(
    __m256d,
    f64,
    4,
    2,
    _mm256_setzero_pd,
    _mm256_loadu_pd,
    _mm256_set1_pd,
    _mm256_fmadd_pd,
    _mm256_storeu_pd,
    |p, v, skip| _mm256_maskstore_pd(p, lanes_avx2::<f64>(0, skip, 4), v)
);
lanes!(
    __m256,
    f32,
    8,
    2,
    _mm256_setzero_ps,
    _mm256_loadu_ps,
    _mm256_set1_ps,
    _mm256_fmadd_ps,
    _mm256_storeu_ps,
    |p, v, skip| _mm256_maskstore_ps(p, lanes_avx2::<f32>(0, skip, 8), v)
);

/// `a · b + c`, rounded once if `FUSED`. Call it from `#[inline(always)]` methods, never from
/// a closure: a closure does not take the kernel's target features, and `mul_add` there is a
/// library call (ten times slower, the history of docs/benchmarks.md).
#[inline(always)]
fn madd<T: Real, const FUSED: bool>(a: T, b: T, c: T) -> T {
    if FUSED {
        a.mul_add(b, c)
    } else {
        c + a * b
    }
}

/// The first `L` values of `s` (a tile, or the part of one that is summed).
#[inline(always)]
fn tile<T, const L: usize>(s: &[T]) -> &[T; L] {
    s[..L].try_into().expect("a whole tile")
}

/// Point `p` (x, y, z) repeated over a tile whose first value is coordinate `phase`.
#[inline(always)]
fn repeated<T: Real>(p: &[T], phase: usize) -> [T; TILE] {
    let p: [T; 3] = p.try_into().expect("three coordinates");
    match phase {
        0 => std::array::from_fn(|l| p[l % 3]),
        1 => std::array::from_fn(|l| p[(l + 1) % 3]),
        _ => std::array::from_fn(|l| p[(l + 2) % 3]),
    }
}

/// The product of the plans' matrices, from the start row with its ring to the final points:
/// `matrix[x'][j]`. Each plan is given as its rows of (old point, weight).
pub(super) fn compose<'a>(
    m: usize,
    plans: impl IntoIterator<Item = Vec<&'a [(usize, f64)]>>,
) -> Vec<Vec<f64>> {
    let mut cur: Vec<Vec<f64>> = (0..m)
        .map(|i| (0..m).map(|j| f64::from(u8::from(i == j))).collect())
        .collect();
    for plan in plans {
        cur = plan
            .iter()
            .map(|parents| {
                let mut row = vec![0.0; m];
                for &(x, w) in *parents {
                    for (r, c) in row.iter_mut().zip(&cur[x]) {
                        *r += w * c;
                    }
                }
                row
            })
            .collect();
    }
    cur
}
