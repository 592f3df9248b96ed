//! The 1D plan of a step: the masks of one extended row in gather form (\[N\] §3, masks by
//! knot insertion; \[G\] §2.2, the bivariate step as the tensor product of two of them).

use super::{combine, grown, Passes, Simd};
use crate::real::{axpy_slab, Real};
use crate::surface::SurfaceError;
use lsubdiv_runtime::curve::CurveTables;
use std::collections::HashMap;

/// The 1D refinement of one extended row (old points x = −1..=N+1) for one step, producing the
/// new points −h..=N'+h: h = 1 (the ring of the next step) except in the last step. It is kept
/// in gather form: per new point, its parents among the old points and their weights, summed
/// in the order of the old points (as the scattered masks would add them).
pub(super) struct Plan {
    /// Per new point X' = −h..=N'+h: the range of its parents in `parents`.
    pub(super) rows: Vec<std::ops::Range<usize>>,
    /// (old point index x + 1, weight).
    pub(super) parents: Vec<(usize, f64)>,
    /// Old side N + 3 (ring included).
    pub(super) old_side: usize,
    /// New side N'.
    pub(super) n_new: i64,
    /// Whether every new point −h..=N'+h has all its parents among the old points −1..=N+1.
    pub(super) complete: bool,
    /// The instruction set its passes run with.
    pub(super) simd: Simd,
}

impl Plan {
    pub(super) fn new(
        t: &CurveTables<'_>,
        lookup: &HashMap<&[u8], u32>,
        w: &[u8],
        h: i64,
    ) -> Result<Plan, SurfaceError> {
        let d = t.degree as i64;
        let n = w.len() as i64;
        let label = |i: i64| w[i.rem_euclid(n) as usize];
        // Off(x): new knot of old knot x (Off(0) = 0).
        let len = |i: i64| t.rule(label(i)).len() as i64;
        let half = (d + 1) / 2;
        // Off(x) for x = −half−1 ..= n + half + 1, by prefix sums (Off(0) = 0).
        let lo_x = -half - 1;
        let mut prefix = vec![0i64];
        for x in lo_x..n + half + 1 {
            prefix.push(prefix.last().copied().unwrap_or(0) + len(x));
        }
        let zero = prefix[(-lo_x) as usize];
        let off = |x: i64| prefix[(x - lo_x) as usize] - zero;
        let n_new = off(n);
        // Scatter every old point's mask, keeping the entries that land on −h..=N'+h.
        let mut by_new: Vec<Vec<(usize, f64)>> = vec![Vec::new(); (n_new + 1 + 2 * h) as usize];
        for x in -1..=n + 1 {
            let word: Vec<u8> = (x - half..x + half).map(label).collect();
            let wi = *lookup
                .get(word.as_slice())
                .ok_or_else(|| SurfaceError::UnknownWord(t.word_str(&word)))?;
            // The entry j of the mask has its middle knot at new knot Off(x − half) + j + half.
            let base = off(x - half) + half;
            for (j, &wt) in t.mask_weights[t.mask_range(wi as usize)].iter().enumerate() {
                let xn = base + j as i64 + h;
                if (0..by_new.len() as i64).contains(&xn) {
                    by_new[xn as usize].push(((x + 1) as usize, wt));
                }
            }
        }
        // Mask weights are non-negative and sum to one at every new point (the compiler's
        // partition-of-unity certificate), so a sum of one means no parent is missing.
        let complete = by_new
            .iter()
            .all(|p| (p.iter().map(|&(_, w)| w).sum::<f64>() - 1.0).abs() <= 1e-9);
        let mut rows = Vec::with_capacity(by_new.len());
        let mut parents = Vec::new();
        for p in by_new {
            rows.push(parents.len()..parents.len() + p.len());
            parents.extend(p);
        }
        Ok(Plan {
            rows,
            parents,
            old_side: (n + 3) as usize,
            n_new,
            complete,
            simd: Simd::detect(),
        })
    }

    /// Per new point, its parents (old point index x + 1, weight).
    pub(super) fn parent_rows(&self) -> Vec<&[(usize, f64)]> {
        self.rows.iter().map(|r| &self.parents[r.clone()]).collect()
    }

    /// Side of the new patch, ring included.
    pub(super) fn new_side(&self) -> usize {
        self.rows.len()
    }

    /// `dst[X'·len ..][..len] = Σ w · src[x·len ..][..len]` over the parents (x, w) of every new
    /// point X' (slabs of `len` values: whole rows of a patch at once). Compiled for the
    /// baseline and AVX2 (the plan's [`Simd`]): the same operations in the same order, so the
    /// same bits, only wider vectors.
    fn pass<T: Real>(&self, src: &[T], len: usize, dst: &mut [T]) {
        self.pass_rows(src, len, 0, dst);
    }

    /// [`Plan::pass`] for the new points X' = `first`, `first` + 1, … that `dst` holds.
    fn pass_rows<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        match self.simd {
            // AVX-512 runs the AVX2 pass: compiled for AVX-512 it was slower on the cube
            // (123–131 against 136–137 M vertices/s, the history of docs/benchmarks.md).
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Simd::Avx2` and `Simd::Avx512` are only handed out where the CPU has AVX2.
            Simd::Avx2 | Simd::Avx512 => unsafe { self.pass_avx2(src, len, first, dst) },
            _ => self.pass_any(src, len, first, dst),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn pass_avx2<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        self.pass_any(src, len, first, dst);
    }

    /// The pass with slabs of a small patch's common lengths made constants (points of
    /// sides 4 to 11), so that a row's sums unroll: a fan face's patch is that small in its
    /// first steps, where the calls and loops per row cost more than the sums.
    #[inline(always)]
    fn pass_any<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        match len {
            12 => self.pass_sized::<T, 12>(src, first, dst),
            15 => self.pass_sized::<T, 15>(src, first, dst),
            18 => self.pass_sized::<T, 18>(src, first, dst),
            21 => self.pass_sized::<T, 21>(src, first, dst),
            24 => self.pass_sized::<T, 24>(src, first, dst),
            27 => self.pass_sized::<T, 27>(src, first, dst),
            30 => self.pass_sized::<T, 30>(src, first, dst),
            33 => self.pass_sized::<T, 33>(src, first, dst),
            _ => self.pass_len(src, len, first, dst),
        }
    }

    #[inline(always)]
    fn pass_sized<T: Real, const L: usize>(&self, src: &[T], first: usize, dst: &mut [T]) {
        self.pass_len(src, L, first, dst);
    }

    #[inline(always)]
    fn pass_len<T: Real>(&self, src: &[T], len: usize, first: usize, dst: &mut [T]) {
        for (row, d) in self.rows[first..].iter().zip(dst.chunks_exact_mut(len)) {
            let slab = |x: usize| &src[x * len..(x + 1) * len];
            let w = |i: usize| T::from_f64(self.parents[row.start + i].1);
            match self.parents[row.clone()] {
                [(a, _)] => combine(d, [w(0)], [slab(a)]),
                [(a, _), (b, _)] => combine(d, [w(0), w(1)], [slab(a), slab(b)]),
                [(a, _), (b, _), (c, _)] => {
                    combine(d, [w(0), w(1), w(2)], [slab(a), slab(b), slab(c)])
                }
                [(a, _), (b, _), (c, _), (e, _)] => combine(
                    d,
                    [w(0), w(1), w(2), w(3)],
                    [slab(a), slab(b), slab(c), slab(e)],
                ),
                ref ps => {
                    d.fill(T::default());
                    for &(x, wt) in ps {
                        axpy_slab(d, T::from_f64(wt), slab(x));
                    }
                }
            }
        }
    }

    /// One step of one large patch: `src` ([a][b], side N+3) is refined along a, transposed,
    /// and refined along b into `dst` ([b'][a'], side `new_side`), strip by strip
    /// ([`Plan::strips`]).
    pub(super) fn step_transposing<T: Real>(
        &self,
        src: &[T],
        p: &mut Passes<T>,
        strip_bytes: usize,
        dst: &mut [T],
    ) {
        let side = self.new_side();
        let dst = &mut dst[..side * side * 3];
        self.strips(src, p, strip_bytes, |a0, w, at, _| {
            if w == side {
                // One strip: the new rows are the whole of `dst`, in one pass.
                self.pass(at, side * 3, dst);
                return;
            }
            for b in 0..side {
                self.pass_rows(at, w * 3, b, &mut dst[(b * side + a0) * 3..][..w * 3]);
            }
        });
    }

    /// [`Plan::step_transposing`] handing each new row b' of each strip to
    /// `each(a0, b', row)` (new points a0.., b') instead of storing the new patch: the last
    /// step of a large patch, whose scratch is then two strips and a row.
    pub(super) fn step_strips<T: Real>(
        &self,
        src: &[T],
        p: &mut Passes<T>,
        strip_bytes: usize,
        mut each: impl FnMut(usize, usize, &[T]),
    ) {
        let side = self.new_side();
        self.strips(src, p, strip_bytes, |a0, w, at, row| {
            let row = grown(row, w * 3);
            for b in 0..side {
                self.pass_rows(at, w * 3, b, row);
                each(a0, b, row);
            }
        });
    }

    /// For each strip of new points a0..a0 + w along a: `f(a0, w, at, row)` with the strip
    /// refined along a and transposed ([`Plan::strip_transposed`]) and the row buffer.
    fn strips<T: Real>(
        &self,
        src: &[T],
        p: &mut Passes<T>,
        strip_bytes: usize,
        mut f: impl FnMut(usize, usize, &[T], &mut Vec<T>),
    ) {
        let side = self.new_side();
        let strip = self.strip_width::<T>(strip_bytes);
        for a0 in (0..side).step_by(strip) {
            let w = strip.min(side - a0);
            let at = self.strip_transposed(src, &mut p.a, &mut p.at, a0, w);
            f(a0, w, at, &mut p.row);
        }
    }

    /// New points along a per strip: as many as `strip_bytes` of rows refined along a hold
    /// (at least one), so that a strip and its transpose stay in cache.
    fn strip_width<T>(&self, strip_bytes: usize) -> usize {
        (strip_bytes / (self.old_side * 3 * size_of::<T>())).max(1)
    }

    /// The new rows a0..a0 + w refined along a (into `a`), transposed into `at` ([b][a'],
    /// N+3 rows of w points).
    fn strip_transposed<'p, T: Real>(
        &self,
        src: &[T],
        a: &mut Vec<T>,
        at: &'p mut Vec<T>,
        a0: usize,
        w: usize,
    ) -> &'p [T] {
        const L: usize = 3;
        let m = self.old_side;
        let a = grown(a, w * m * L);
        self.pass_rows(src, m * L, a0, a);
        let at = grown(at, m * w * L);
        for (xn, column) in a.chunks_exact(m * L).enumerate() {
            for (y, q) in column.chunks_exact(L).enumerate() {
                let d = (y * w + xn) * L;
                at[d..d + L].copy_from_slice(q);
            }
        }
        at
    }
}
