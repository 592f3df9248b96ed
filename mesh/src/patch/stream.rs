//! Writing runs of the output in whole cache lines.
//!
//! A worker writes its ordinary faces' interior points in one long ascending run (consecutive
//! faces own consecutive interiors, row by row: `Numbering`), their edges in another, and a fan
//! face's last level one run per row (strip after strip). `Stream` holds the part of a 64-byte
//! line not yet complete and writes each line the run fills whole with a non-temporal store
//! (past the caches, without reading the line first); lines the run only partly covers are
//! written with plain stores, so no byte outside the run is touched. Non-temporal stores pay
//! only when the output is larger than the caches: below [`STREAM_BYTES`] every line is a
//! plain store.

use std::marker::PhantomData;

use super::Simd;

/// Output size from which whole lines are written non-temporally: measured on the torus (an
/// Intel host, 2 MiB of L2 a core), streaming is 15 % faster at 12.4 MB, even at 6.3 MB and
/// 3 % slower at 3 MB (the history of docs/benchmarks.md).
pub(super) const STREAM_BYTES: usize = 8 << 20;

const LINE: usize = 64;

/// Writes runs of values into a buffer that several workers share at disjoint indices.
pub(super) struct Stream<'a, T> {
    base: *mut T,
    len: usize,
    /// Index after the last value handed.
    next: usize,
    /// The values handed that end at `next`, not yet written: all in the line of `next − 1`
    /// (a line holds at most 16 values of a 4-byte scalar).
    held: [T; 16],
    count: usize,
    streaming: bool,
    /// How lines go out: one 64-byte store (AVX-512F), two of 32 bytes (AVX2) or four of 16
    /// (SSE2, the baseline); with AVX-512F or AVX2 a partial line is also completed, and a
    /// run's tail held, by masked loads.
    simd: Simd,
    out: PhantomData<&'a mut [T]>,
}

impl<'a, T: Copy + Default> Stream<'a, T> {
    /// A writer into `len` values at `base` (non-temporal where `streaming`), with the
    /// vectors of `simd`.
    ///
    /// # Safety
    /// `base` is valid for `len` values for `'a`, and no one else reads or writes the indices
    /// this writer is handed until [`Stream::finish`] and then [`fence`] on this thread; `simd`
    /// only a path the CPU has (it pays where the code calling [`Stream::run`] is compiled for
    /// it).
    pub(super) unsafe fn new(
        base: *mut T,
        len: usize,
        streaming: bool,
        simd: Simd,
    ) -> Stream<'a, T> {
        Stream {
            base,
            len,
            next: 0,
            held: [T::default(); 16],
            count: 0,
            streaming,
            simd,
            out: PhantomData,
        }
    }

    /// Values per line.
    fn per_line() -> usize {
        LINE / size_of::<T>()
    }

    /// Position of index i in its line.
    fn in_line(&self, i: usize) -> usize {
        (self.base as usize + i * size_of::<T>()) % LINE / size_of::<T>()
    }

    /// Hands `values` for the indices `at..`.
    ///
    /// # Safety
    /// The indices are this writer's (see [`Stream::new`]).
    #[inline(always)]
    pub(super) unsafe fn run(&mut self, at: usize, mut values: &[T]) {
        assert!(at + values.len() <= self.len, "output index in range");
        let per = Self::per_line();
        if at != self.next {
            // SAFETY: the held values are this writer's (the function's contract).
            unsafe { self.flush() };
            self.next = at;
        }
        // The line of `next`, if the run does not start it: complete it from the values.
        let off = self.in_line(self.next);
        if off != 0 || self.count != 0 {
            let take = (per - off).min(values.len());
            if self.count + take == per && self.streaming && self.simd != Simd::Baseline {
                // SAFETY: a whole aligned line of this writer's indices, all handed: the held
                // ones and the first `take` values.
                unsafe { self.joined(self.next - self.count, values.as_ptr()) };
                self.count = 0;
                self.next += take;
                values = &values[take..];
            } else {
                copy(
                    &mut self.held[self.count..self.count + take],
                    &values[..take],
                );
                self.count += take;
                self.next += take;
                values = &values[take..];
                if off + take < per {
                    return;
                }
                if self.count == per {
                    // SAFETY: a whole aligned line of this writer's indices, all handed.
                    unsafe { self.line(self.next - per, self.held.as_ptr()) };
                    self.count = 0;
                } else {
                    // SAFETY: the held values are this writer's.
                    unsafe { self.flush() };
                }
            }
        }
        // Whole lines, then the start of the next one, held.
        let whole = values.len() / per * per;
        // SAFETY: whole aligned lines of this writer's indices.
        unsafe { self.lines(self.next, values.as_ptr(), whole / per) };
        self.next += whole;
        let tail = &values[whole..];
        self.hold(tail);
        self.count = tail.len();
        self.next += tail.len();
    }

    /// Writes the line at `at` (non-temporally, in one 64-byte store or two of 32) from the
    /// held values and, after them, those at `rest`. The held ones were stored a run ago; the
    /// rest are loaded where they are: a 64-byte load of values just copied next to them would
    /// wait for every store before it (the store buffer cannot forward it), the lines in
    /// flight included.
    ///
    /// # Safety
    /// As [`Stream::line`]; `rest` holds the line's values after the held ones; the CPU has
    /// AVX-512F or AVX2 (`self.simd`).
    #[inline(always)]
    unsafe fn joined(&self, at: usize, rest: *const T) {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: the caller's contract; the masked loads read only the lanes they keep (the
        // held ones from `held`, the others from `rest`).
        unsafe {
            use std::arch::x86_64::*;
            let (held, from) = (self.held.as_ptr(), rest.wrapping_sub(self.count));
            let dst = self.base.add(at);
            if self.simd == Simd::Avx2 {
                for h in 0..2 {
                    let keep = lanes_avx2::<T>(h, self.count, Self::per_line());
                    let old = _mm256_loadu_si256(held.cast::<__m256i>().add(h));
                    let new = half_avx2::<T>(from, h, keep);
                    let v = _mm256_blendv_epi8(old, new, keep);
                    _mm256_stream_si256(dst.cast::<__m256i>().add(h), v);
                }
                return;
            }
            let old = _mm512_loadu_si512(held.cast());
            let v = if size_of::<T>() == 8 {
                let keep = (0xffu32 << self.count) as u8;
                _mm512_mask_loadu_epi64(old, keep, from.cast())
            } else {
                let keep = (0xffffu32 << self.count) as u16;
                _mm512_mask_loadu_epi32(old, keep, from.cast())
            };
            _mm512_stream_si512(dst.cast(), v);
        }
    }

    /// Holds `tail` (less than a line) at the start of `held`: by masked loads (of one 64-byte
    /// vector, or two of 32 bytes) where the path has them, else value by value.
    #[inline(always)]
    fn hold(&mut self, tail: &[T]) {
        assert!(tail.len() < Self::per_line(), "less than a line");
        let (from, to) = (tail.as_ptr(), self.held.as_mut_ptr());
        match self.simd {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the CPU has AVX-512F (`Stream::new`'s contract); the masked load reads
            // only the tail's lanes, and `held` has room for a whole line.
            Simd::Avx512 => unsafe {
                use std::arch::x86_64::*;
                let keep = (1u32 << tail.len()) - 1;
                let v = if size_of::<T>() == 8 {
                    _mm512_maskz_loadu_epi64(keep as u8, from.cast())
                } else {
                    _mm512_maskz_loadu_epi32(keep as u16, from.cast())
                };
                _mm512_storeu_si512(to.cast(), v);
            },
            #[cfg(target_arch = "x86_64")]
            // SAFETY: the CPU has AVX2 (`Stream::new`'s contract); each masked load reads only
            // the tail's lanes, and `held` has room for a whole line.
            Simd::Avx2 => unsafe {
                use std::arch::x86_64::*;
                for h in 0..2 {
                    let v = half_avx2::<T>(from, h, lanes_avx2::<T>(h, 0, tail.len()));
                    _mm256_storeu_si256(to.cast::<__m256i>().add(h), v);
                }
            },
            _ => copy(&mut self.held[..tail.len()], tail),
        }
    }

    /// Writes the held values with plain stores.
    unsafe fn flush(&mut self) {
        let at = self.next - self.count;
        for (i, v) in self.held[..self.count].iter().enumerate() {
            // SAFETY: in range (checked when handed) and this writer's.
            unsafe { self.base.add(at + i).write(*v) };
        }
        self.count = 0;
    }

    /// Writes one whole aligned line at index `at` from the line's values at `values`.
    #[inline(always)]
    unsafe fn line(&self, at: usize, values: *const T) {
        // SAFETY: the caller's contract.
        unsafe { self.lines(at, values, 1) };
    }

    /// Writes `count` whole aligned lines from index `at` on, from the lines' values at
    /// `values` (the path chosen once, not per line).
    #[inline(always)]
    unsafe fn lines(&self, at: usize, values: *const T, count: usize) {
        let len = count * Self::per_line();
        // SAFETY: `at..at + len` is in range and this writer's (the caller's contract), and
        // the lines are aligned to 64 bytes, so every 16 or 32 bytes of them are aligned.
        unsafe {
            let dst = self.base.add(at);
            #[cfg(target_arch = "x86_64")]
            if self.streaming {
                use std::arch::x86_64::*;
                match self.simd {
                    // The CPU has the path's instructions (`Stream::new`'s contract).
                    Simd::Avx512 => {
                        let (d, s) = (dst.cast::<__m512i>(), values.cast::<__m512i>());
                        for k in 0..count {
                            _mm512_stream_si512(d.add(k), _mm512_loadu_si512(s.add(k)));
                        }
                    }
                    Simd::Avx2 => {
                        let (d, s) = (dst.cast::<__m256i>(), values.cast::<__m256i>());
                        for k in 0..count * LINE / 32 {
                            _mm256_stream_si256(d.add(k), _mm256_loadu_si256(s.add(k)));
                        }
                    }
                    Simd::Baseline => {
                        // SSE2: every x86-64.
                        let (d, s) = (dst.cast::<__m128i>(), values.cast::<__m128i>());
                        for k in 0..count * LINE / 16 {
                            _mm_stream_si128(d.add(k), _mm_loadu_si128(s.add(k)));
                        }
                    }
                }
                return;
            }
            std::ptr::copy_nonoverlapping(values, dst, len);
        }
    }

    /// Writes what is held. The worker calls [`fence`] once after its last writer: the
    /// fence waits for every line in flight, so one per row of a small face would cost more
    /// than the face's rows (each fence drains the write-combining buffers).
    pub(super) fn finish(mut self) {
        // SAFETY: the held values are this writer's.
        unsafe { self.flush() };
    }
}

/// A few [`Stream`]s, each run handed to the one it continues (or, if none, to the next in
/// turn): a worker whose faces' runs interleave several ascending runs (faces taken
/// column by column of a grid whose interiors are numbered row by row) still writes whole
/// lines.
pub(super) struct Writers<'a, T> {
    pool: Vec<Stream<'a, T>>,
    /// The writer used last, and the one to take next for a run that continues none.
    last: usize,
    victim: usize,
}

/// Writers in a pool: enough for every face of the longest chain (`patch::STACK_FACES`)
/// and its edges, with room.
pub(super) const WRITERS: usize = 16;

impl<'a, T: Copy + Default> Writers<'a, T> {
    /// `count` writers from `make` (see [`Stream::new`] for its contract).
    pub(super) fn new(count: usize, make: impl FnMut(usize) -> Stream<'a, T>) -> Self {
        Writers {
            pool: (0..count.max(1)).map(make).collect(),
            last: 0,
            victim: 0,
        }
    }

    /// Hands `values` for the indices `at..` to the writer whose run they continue.
    ///
    /// # Safety
    /// As [`Stream::run`].
    #[inline(always)]
    pub(super) unsafe fn run(&mut self, at: usize, values: &[T]) {
        if self.pool[self.last].next != at {
            self.last = self.pick(at);
        }
        // SAFETY: the caller's contract.
        unsafe { self.pool[self.last].run(at, values) };
    }

    /// The writer whose run `at` continues, or the next in turn (out of the hot path: a
    /// worker's faces mostly continue the run of the face before).
    #[cold]
    #[inline(never)]
    fn pick(&mut self, at: usize) -> usize {
        self.pool
            .iter()
            .position(|s| s.next == at)
            .unwrap_or_else(|| {
                let i = self.victim;
                self.victim = (self.victim + 1) % self.pool.len();
                i
            })
    }

    /// Writes what every writer holds.
    pub(super) fn finish(self) {
        self.pool.into_iter().for_each(Stream::finish);
    }
}

/// Orders the non-temporal stores of this thread's writers before anything that follows (a
/// thread that reads the output after joining this one sees them).
pub(super) fn fence() {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE2 is part of x86-64.
    unsafe {
        std::arch::x86_64::_mm_sfence()
    };
}

/// AVX2: a mask of the lanes of 32-byte half `h` of a line of `T` whose index in the line
/// is in `from..to` (every bit of a lane set); half 0 is also a single vector's lanes.
///
/// # Safety
/// The CPU has AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(super) unsafe fn lanes_avx2<T>(h: usize, from: usize, to: usize) -> std::arch::x86_64::__m256i {
    use std::arch::x86_64::*;
    // SAFETY: AVX2 (the caller's contract).
    unsafe {
        if size_of::<T>() == 8 {
            let i = _mm256_add_epi64(
                _mm256_setr_epi64x(0, 1, 2, 3),
                _mm256_set1_epi64x(4 * h as i64),
            );
            let above = _mm256_cmpgt_epi64(i, _mm256_set1_epi64x(from as i64 - 1));
            _mm256_and_si256(above, _mm256_cmpgt_epi64(_mm256_set1_epi64x(to as i64), i))
        } else {
            let i = _mm256_add_epi32(
                _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7),
                _mm256_set1_epi32(8 * h as i32),
            );
            let above = _mm256_cmpgt_epi32(i, _mm256_set1_epi32(from as i32 - 1));
            _mm256_and_si256(above, _mm256_cmpgt_epi32(_mm256_set1_epi32(to as i32), i))
        }
    }
}

/// AVX2: the lanes `keep` ([`lanes_avx2`]) of 32-byte half `h` of the line of `T` at `p`,
/// zero elsewhere; only the kept lanes are read.
///
/// # Safety
/// The CPU has AVX2; `p` holds the kept lanes.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn half_avx2<T>(
    p: *const T,
    h: usize,
    keep: std::arch::x86_64::__m256i,
) -> std::arch::x86_64::__m256i {
    use std::arch::x86_64::*;
    // SAFETY: AVX2 and the kept lanes (the caller's contract); masked-off lanes are not read.
    unsafe {
        if size_of::<T>() == 8 {
            _mm256_maskload_epi64(p.cast::<i64>().add(4 * h), keep)
        } else {
            _mm256_maskload_epi32(p.cast::<i32>().add(8 * h), keep)
        }
    }
}

/// `dst.copy_from_slice(src)` in whole 8-value moves and single values: short runs of a
/// length known only at run time, without a call to the library's `memcpy`.
#[inline(always)]
fn copy<T: Copy>(dst: &mut [T], src: &[T]) {
    let mut d = dst.chunks_exact_mut(8);
    let mut s = src.chunks_exact(8);
    for (d, s) in (&mut d).zip(&mut s) {
        let s: &[T; 8] = s.try_into().expect("8 values");
        let d: &mut [T; 8] = d.try_into().expect("8 values");
        *d = *s;
    }
    for (d, s) in d.into_remainder().iter_mut().zip(s.remainder()) {
        *d = *s;
    }
}
