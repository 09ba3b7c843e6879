//! The forward and backward passes of zero-phase filtering over channels side by side
//! (a row-major block, one row per sample), the inner loop of the decimation of the
//! regressor channels and of the positions' low-pass.
//!
//! On x86-64 processors with AVX2 and FMA (four channels per instruction) or AVX-512
//! (eight), the passes hold a lane of channels' section states in registers and carry
//! the lane through every section for a tile of rows, then the next lane over the same
//! rows while they are in the first-level cache; their multiplications and additions are
//! fused. Elsewhere they go section by section over every channel of a row, unfused, as
//! [`Sos::filtfilt`](super::Sos::filtfilt) does. Every channel goes through the same
//! operations whatever the lane it falls in, so on one processor a channel's values do
//! not depend on the channels filtered beside it; the fused instances differ from the
//! unfused code by rounding only (docs/performance.md#streaming-identification).

/// Bytes of a tile of rows, which the lanes take in turn: they stay in the first-level
/// cache (64 rows of a group of 32 channels).
const TILE_BYTES: usize = 16 * 1024;

/// Rows ahead of the one filtered whose lane is asked of the memory: a lane reads one
/// cache line per row, which the regressor's fill has just written from another core, and
/// a load's latency would otherwise stall the sections' chain (7 % of the hour's
/// identification time on the project's machine).
const PREFETCH_ROWS: usize = 16;

/// Rows of a block the passes must leave filtered: every `every`-th row from row `first`
/// (the rows a decimation keeps), or every row (`every = 1`, `first = 0`). The backward
/// pass computes every row but stores only these, which spares the writing back of the
/// rows a decimation drops (nine in ten of the block's cache lines stay clean); the
/// values stored are the same to the bit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Kept {
    /// The step between kept rows (at least 1).
    pub(crate) every: usize,
    /// The first kept row (below `every`).
    pub(crate) first: usize,
}

impl Kept {
    /// Every row.
    pub(crate) const ALL: Kept = Kept { every: 1, first: 0 };
}

/// Where the backward pass may store the rows it keeps among `rows`, packed: row
/// `rows.start + i * every` goes to row `at + i` of the block instead of its own, so that
/// a decimation takes them as one slice, written last (in the cache), instead of reading
/// each from its place, long since gone from the cache (1.7 % of the hour's
/// identification). The backward pass goes down the rows: row `at + i` must be at or
/// after row `rows.start + i * every` (already filtered when written). `rows.start` must
/// be a kept row; rows the pass keeps outside `rows` are stored at their own rows, those
/// among `at..` overwritten.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Take {
    /// The rows of the block whose kept rows are packed.
    pub(crate) rows: std::ops::Range<usize>,
    /// The row the first of them goes to.
    pub(crate) at: usize,
}

impl Take {
    /// The number of rows kept among `rows`, one in `every`.
    pub(crate) fn count(&self, every: usize) -> usize {
        self.rows.len().div_ceil(every)
    }
}

/// Where the forward pass starts and the section states it hands on: a decimation run
/// block by block over a record carries its forward states from each block to the next
/// instead of filtering an overlap on the left of every block again
/// (docs/performance.md#streaming-identification).
pub(crate) struct Forward<'a> {
    /// The first row both passes filter; the rows before it are neither read nor written.
    pub(crate) from: usize,
    /// The section states before row `from`, `S` pairs per channel (channel after
    /// channel, the sections in order); `None`: the steady state of row `from`'s values.
    pub(crate) start: Option<&'a [[f64; 2]]>,
    /// A row and a buffer (`S` pairs per channel, laid out as `start`) for the forward
    /// pass's states before that row (a row past the last: its states after the last).
    pub(crate) hand: Option<(usize, &'a mut [[f64; 2]])>,
}

impl Forward<'_> {
    /// Every row, from the steady state of the first, nothing handed on.
    pub(crate) fn whole<'b>() -> Forward<'b> {
        Forward {
            from: 0,
            start: None,
            hand: None,
        }
    }
}

/// The channels a block of `g` channels filtered side by side by a cascade of `sections`
/// sections is best laid out with: `g` rounded up to a multiple of 8, the channels added
/// being zeros, which stay zeros and leave the others' values as they are (every channel
/// goes through the same operations whatever the lane it falls in), so that the passes
/// take whole lanes (8 channels with AVX2; 16 with AVX-512, or 8 when 16 do not divide
/// the block); `g` itself where the passes take no lanes (one channel, more than four
/// sections, no AVX2). A partial lane is copied row by row into a buffer of full lanes
/// and back, two calls of `memcpy` per row and pass, which cost the hour's identification
/// 2 to 3 % of its time (the last group of its regressor channels, the positions'
/// low-pass, the prediction's torques); a lane of 16 for 7 channels would double the
/// bytes of the block the passes go through (a lane of seven channels is bound by its
/// sections' latency, not by its width).
pub(crate) fn padded_width(g: usize, sections: usize) -> usize {
    if g <= 1 || lane_width(sections) <= 1 {
        g
    } else {
        g.next_multiple_of(8)
    }
}

/// The channels of the widest lane of [`passes_taking`] on this processor for a cascade
/// of `sections` sections (1: it takes no lanes).
fn lane_width(sections: usize) -> usize {
    if !(1..=4).contains(&sections) {
        return 1;
    }
    #[cfg(all(target_arch = "x86_64", feature = "std"))]
    if std::is_x86_feature_detected!("avx512f") && crate::trig::vector_available() {
        return 16;
    }
    #[cfg(target_arch = "x86_64")]
    if crate::trig::vector_available() {
        return 8;
    }
    1
}

/// The forward pass from the steady state of the first row, then the backward pass from
/// that of the last, over `g` channels of the row-major `ext`, in place; the backward
/// pass stores the rows `kept` only (the others hold the forward pass's values). `zi` is
/// the cascade's steady state per unit input. The rows, the forward pass's first states
/// and the states it hands on are `forward`'s ([`Forward::whole`]: every row); a
/// channel's values are the same to the bit as when the forward pass runs over the rows
/// before `forward.from` in the same call and hands its states on there.
///
/// With `take`, the backward pass packs the rows it keeps among `take.rows` from row
/// `take.at` on ([`Take`]) when it can, and returns whether it did (else they are at their
/// own rows). It can with lanes of channels (AVX2 or AVX-512, up to four sections) and no
/// partial lane ([`padded_width`]); the values are the same to the bit either way.
pub(super) fn passes_taking(
    sections: &[[f64; 6]],
    zi: &[[f64; 2]],
    ext: &mut [f64],
    g: usize,
    kept: Kept,
    mut forward: Forward<'_>,
    mut take: Option<Take>,
) -> bool {
    if let Some(t) = &take {
        let m = t.count(kept.every);
        assert!(
            kept.every > 0 && t.rows.start % kept.every == kept.first,
            "the rows taken start at a kept row"
        );
        // row at + i at or after row rows.start + i * every, for every i below m
        assert!(
            m == 0
                || (t.at >= t.rows.start + (m - 1) * (kept.every - 1)
                    && (t.at + m) * g <= ext.len()
                    && t.rows.end * g <= ext.len()),
            "the rows taken go to rows already filtered: {t:?}, {m} rows, {} rows in all",
            ext.len() / g.max(1)
        );
    }
    if let Some(start) = forward.start {
        assert_eq!(start.len(), g * sections.len(), "starting states");
    }
    if let Some((_, out)) = &forward.hand {
        assert_eq!(out.len(), g * sections.len(), "handed states");
    }
    #[cfg(all(target_arch = "x86_64", feature = "std"))]
    if std::is_x86_feature_detected!("avx512f") && crate::trig::vector_available() {
        // SAFETY: the CPU has AVX-512F, AVX2 and FMA, the features of `passes_avx512`.
        return unsafe { passes_avx512(sections, zi, ext, g, kept, &mut forward, &mut take) };
    }
    #[cfg(target_arch = "x86_64")]
    if crate::trig::vector_available() {
        // SAFETY: the CPU has AVX2 and FMA, the features `passes_avx2` is compiled for.
        return unsafe { passes_avx2(sections, zi, ext, g, kept, &mut forward, &mut take) };
    }
    by_section::<false>(sections, zi, ext, g, &mut forward);
    false
}

/// The tiled passes in lanes of eight channels (two vectors of four side by side), fused.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn passes_avx2(
    sections: &[[f64; 6]],
    zi: &[[f64; 2]],
    ext: &mut [f64],
    g: usize,
    kept: Kept,
    forward: &mut Forward<'_>,
    take: &mut Option<Take>,
) -> bool {
    tiled::<8>(sections, zi, ext, g, kept, forward, take)
}

/// The tiled passes in lanes of sixteen channels (two vectors of eight side by side: the
/// sections' chains of one vector wait on their fused operations' latency, which the
/// other's fill), fused.
///
/// # Safety
/// The CPU must support AVX-512F, AVX2 and FMA.
#[cfg(all(target_arch = "x86_64", feature = "std"))]
#[target_feature(enable = "avx512f,avx2,fma")]
unsafe fn passes_avx512(
    sections: &[[f64; 6]],
    zi: &[[f64; 2]],
    ext: &mut [f64],
    g: usize,
    kept: Kept,
    forward: &mut Forward<'_>,
    take: &mut Option<Take>,
) -> bool {
    // a block of whole lanes of 8 but not of 16 (7 channels padded to 8: the positions'
    // low-pass, the prediction's torques) in lanes of 8, not a partial lane of 16
    if !g.is_multiple_of(16) && g.is_multiple_of(8) {
        tiled::<8>(sections, zi, ext, g, kept, forward, take)
    } else {
        tiled::<16>(sections, zi, ext, g, kept, forward, take)
    }
}

#[cfg(target_arch = "x86_64")]
/// The tiled passes in lanes of `W` channels, for cascades of up to four sections (eighth
/// order: every decimation filter); longer cascades and a single channel go section by
/// section, fused too.
#[inline(always)]
fn tiled<const W: usize>(
    sections: &[[f64; 6]],
    zi: &[[f64; 2]],
    ext: &mut [f64],
    g: usize,
    kept: Kept,
    forward: &mut Forward<'_>,
    take: &mut Option<Take>,
) -> bool {
    if g == 1 {
        // one channel is a lane of one: the sections' latency bounds it either way
        by_section::<true>(sections, zi, ext, g, forward);
        return false;
    }
    match sections.len() {
        1 => tiled_sections::<1, W>(sections, zi, ext, g, kept, forward, take),
        2 => tiled_sections::<2, W>(sections, zi, ext, g, kept, forward, take),
        3 => tiled_sections::<3, W>(sections, zi, ext, g, kept, forward, take),
        4 => tiled_sections::<4, W>(sections, zi, ext, g, kept, forward, take),
        _ => {
            by_section::<true>(sections, zi, ext, g, forward);
            false
        }
    }
}

#[cfg(target_arch = "x86_64")]
/// [`tiled`] for `S` sections: the channels `0..g` in lanes of `W`, the last one padded
/// when `W` does not divide `g`; the kept rows stored into `take` when there is no such
/// partial lane (returns whether they were).
#[inline(always)]
fn tiled_sections<const S: usize, const W: usize>(
    sections: &[[f64; 6]],
    zi: &[[f64; 2]],
    ext: &mut [f64],
    g: usize,
    kept: Kept,
    forward: &mut Forward<'_>,
    take: &mut Option<Take>,
) -> bool {
    let sections: &[[f64; 6]; S] = sections.try_into().expect("S sections");
    let zi: &[[f64; 2]; S] = zi.try_into().expect("S steady states");
    let lanes: Vec<Lane> = (0..g)
        .step_by(W)
        .map(|c| Lane {
            first: c,
            width: W.min(g - c),
        })
        .collect();
    let (full, partial) = lanes.split_at(g / W);
    let taking = partial.is_empty() && take.is_some();
    let take = if taking { take } else { &mut None };
    // called, not taken as a pointer: a function called through a pointer is not inlined
    // into the caller's target features (AVX2, AVX-512)
    let lanes = [full, partial];
    if unit_after_first(sections) {
        full_and_partial::<S, W, true>(sections, zi, ext, g, lanes, kept, forward, take);
    } else {
        full_and_partial::<S, W, false>(sections, zi, ext, g, lanes, kept, forward, take);
    }
    taking
}

/// [`tiled_lanes`] of the `full` lanes (the kept rows into `take`), then of the `partial`
/// one.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn full_and_partial<const S: usize, const W: usize, const UNIT: bool>(
    sections: &[[f64; 6]; S],
    zi: &[[f64; 2]; S],
    ext: &mut [f64],
    g: usize,
    [full, partial]: [&[Lane]; 2],
    kept: Kept,
    forward: &mut Forward<'_>,
    take: &mut Option<Take>,
) {
    tiled_lanes::<S, W, false, UNIT>(sections, zi, ext, g, full, kept, forward, take);
    tiled_lanes::<S, W, true, UNIT>(sections, zi, ext, g, partial, kept, forward, &mut None);
}

/// Whether every section but the first has the numerator `[1, 2, 1]` (a low-pass's
/// double zero at -1 with the gain in the first section: every Butterworth and Chebyshev
/// cascade of even order [`design`](super::design) builds), which [`section_unit`]
/// filters with fewer multiplications.
fn unit_after_first(sections: &[[f64; 6]]) -> bool {
    sections
        .iter()
        .skip(1)
        .all(|s| s[0] == 1.0 && s[1] == 2.0 && s[2] == 1.0)
}

/// Channels `first..first + width` of a group, filtered together.
#[derive(Clone, Copy)]
struct Lane {
    first: usize,
    width: usize,
}

#[cfg(target_arch = "x86_64")]
/// Both passes of `lanes` (each of `W` channels, or fewer when `PARTIAL`), tile by tile
/// of rows, each lane's section states kept between tiles; the backward pass stores the
/// rows `kept` only (those among `take`'s rows into `take`, when full lanes); the rows,
/// first states and handed states of `forward`. A partial lane's tile is copied into a
/// buffer of full lanes, padded with zeros, filtered there and copied back.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn tiled_lanes<const S: usize, const W: usize, const PARTIAL: bool, const UNIT: bool>(
    sections: &[[f64; 6]; S],
    zi: &[[f64; 2]; S],
    ext: &mut [f64],
    g: usize,
    lanes: &[Lane],
    kept: Kept,
    forward: &mut Forward<'_>,
    take: &mut Option<Take>,
) {
    let rows = ext.len() / g;
    let from = forward.from.min(rows);
    let n = rows - from;
    if lanes.is_empty() || n == 0 {
        return;
    }
    let tile = (TILE_BYTES / (8 * g.max(W))).max(1);
    let mut buffer = vec![0.0; if PARTIAL { tile * W } else { 0 }];
    // per lane: the first and the second state of each section
    let mut states = vec![[[[0.0; W]; S]; 2]; lanes.len()];
    // the forward pass's rows before the handed states, counted from `from`
    let cut = forward
        .hand
        .as_ref()
        .map_or(n, |(r, _)| r.saturating_sub(from).min(n));
    for backward in [false, true] {
        let row = |i: usize| if backward { rows - 1 - i } else { from + i };
        for ([p, q], lane) in states.iter_mut().zip(lanes) {
            match forward.start.filter(|_| !backward) {
                Some(start) => {
                    for l in 0..lane.width {
                        for s in 0..S {
                            [p[s][l], q[s][l]] = start[(lane.first + l) * S + s];
                        }
                    }
                }
                None => {
                    let x = &ext[row(0) * g + lane.first..][..lane.width];
                    for s in 0..S {
                        for (l, x) in x.iter().enumerate() {
                            p[s][l] = zi[s][0] * x;
                            q[s][l] = zi[s][1] * x;
                        }
                    }
                }
            }
        }
        let parts = if backward {
            [0..n, n..n]
        } else {
            [0..cut, cut..n]
        };
        for (part, range) in parts.into_iter().enumerate() {
            for start in range.clone().step_by(tile) {
                let end = (start + tile).min(range.end);
                for (state, lane) in states.iter_mut().zip(lanes) {
                    if PARTIAL {
                        let (from, to) = (lane.first, lane.first + lane.width);
                        for (i, b) in (start..end).zip(buffer.chunks_exact_mut(W)) {
                            for (b, x) in b.iter_mut().zip(&ext[row(i) * g..][from..to]) {
                                *b = *x;
                            }
                        }
                        let buffer = &mut buffer[..(end - start) * W];
                        lane_rows::<S, W, UNIT>(
                            sections,
                            state,
                            buffer,
                            W,
                            0,
                            0..end - start,
                            (0, None),
                            None,
                        );
                        for (i, b) in (start..end).zip(buffer.chunks_exact(W)) {
                            for (x, b) in ext[row(i) * g..][from..to].iter_mut().zip(b) {
                                *x = *b;
                            }
                        }
                    } else {
                        let ahead = (PREFETCH_ROWS * g) as isize;
                        let ahead = if backward { -ahead } else { ahead };
                        lane_rows::<S, W, UNIT>(
                            sections,
                            state,
                            ext,
                            g,
                            lane.first,
                            (start..end).map(row),
                            (ahead, backward.then_some(kept)),
                            take.as_mut().filter(|_| backward),
                        );
                    }
                }
            }
            if !backward
                && part == 0
                && let Some((_, out)) = forward.hand.as_mut()
            {
                for ([p, q], lane) in states.iter().zip(lanes) {
                    for l in 0..lane.width {
                        for s in 0..S {
                            out[(lane.first + l) * S + s] = [p[s][l], q[s][l]];
                        }
                    }
                }
            }
        }
    }
}

#[cfg(target_arch = "x86_64")]
/// One pass of the channels `c..c + W` of `ext` (`g` per row) over `rows`, in their
/// order, from and to the section states `state`, fused; each row's lane prefetched
/// `ahead` entries before it is read (0: none); only the rows `kept` stored (`None`:
/// every row; `Some`: `rows` must go down one by one, as the backward pass does), those
/// among `take`'s rows into `take` (with `kept` only).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn lane_rows<const S: usize, const W: usize, const UNIT: bool>(
    sections: &[[f64; 6]; S],
    state: &mut [[[f64; W]; S]; 2],
    ext: &mut [f64],
    g: usize,
    c: usize,
    rows: impl Iterator<Item = usize>,
    (ahead, kept): (isize, Option<Kept>),
    take: Option<&mut Take>,
) {
    let [mut p, mut q] = *state;
    // the row's remainder modulo `every`, counted down with the rows (a division per row
    // would cost more than the stores it spares)
    let mut rows = rows.peekable();
    let (every, first) = kept.map_or((1, 0), |k| (k.every, k.first));
    let mut phase = rows.peek().map_or(0, |&r| r % every);
    // the row the next kept row among `take`'s goes to, once one went (the rows go down:
    // one less at each)
    let mut slot: Option<usize> = None;
    for r in rows {
        if ahead != 0 {
            let at = ext.as_ptr().wrapping_offset((r * g + c) as isize + ahead);
            // SAFETY: a prefetch reads nothing and faults on no address
            unsafe {
                core::arch::x86_64::_mm_prefetch::<{ core::arch::x86_64::_MM_HINT_T0 }>(at.cast())
            };
        }
        let x: &[f64; W] = (&ext[r * g + c..r * g + c + W])
            .try_into()
            .expect("W channels");
        let mut v = *x;
        for s in 0..S {
            for l in 0..W {
                v[l] = if UNIT && s > 0 {
                    section_unit(&sections[s], v[l], &mut p[s][l], &mut q[s][l])
                } else {
                    section::<true>(&sections[s], v[l], &mut p[s][l], &mut q[s][l])
                };
            }
        }
        let to = if kept.is_none() {
            Some(r)
        } else if phase == first {
            match take.as_ref().filter(|t| t.rows.contains(&r)) {
                Some(t) => {
                    let to = slot.unwrap_or_else(|| t.at + (r - t.rows.start) / every);
                    slot = to.checked_sub(1);
                    Some(to)
                }
                None => Some(r),
            }
        } else {
            None
        };
        if let Some(to) = to {
            let out: &mut [f64; W] = (&mut ext[to * g + c..to * g + c + W])
                .try_into()
                .expect("W channels");
            *out = v;
        }
        phase = if phase == 0 { every - 1 } else { phase - 1 };
    }
    *state = [p, q];
}

/// One channel `x` through the cascade `sections` from and to the section states
/// `state` (each `[p, q]`), in the order of its samples or from the last (`backward`), in
/// place: the operations [`passes_taking`] applies to each channel on this processor (fused
/// where it fuses them), so that a zero-phase filter run block by block, its states carried
/// from block to block, gives [`Sos::filtfilt`](super::Sos::filtfilt)'s values to the bit.
pub(crate) fn pass(sections: &[[f64; 6]], state: &mut [[f64; 2]], x: &mut [f64], backward: bool) {
    #[cfg(target_arch = "x86_64")]
    if crate::trig::vector_available() {
        // SAFETY: the CPU has AVX2 and FMA, the features `pass_fused` is compiled for.
        unsafe { pass_fused(sections, state, x, backward) };
        return;
    }
    pass_with::<false>(sections, state, x, backward);
}

/// [`pass_with`] fused, compiled for AVX2 and FMA.
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn pass_fused(sections: &[[f64; 6]], state: &mut [[f64; 2]], x: &mut [f64], backward: bool) {
    pass_with::<true>(sections, state, x, backward);
}

/// The samples of `x` through every section in turn, in order or from the last.
#[inline(always)]
fn pass_with<const FUSED: bool>(
    sections: &[[f64; 6]],
    state: &mut [[f64; 2]],
    x: &mut [f64],
    backward: bool,
) {
    let mut step = |v: &mut f64| {
        let mut cur = *v;
        for (s, [p, q]) in sections.iter().zip(state.iter_mut()) {
            cur = section::<FUSED>(s, cur, p, q);
        }
        *v = cur;
    };
    if backward {
        x.iter_mut().rev().for_each(&mut step);
    } else {
        x.iter_mut().for_each(&mut step);
    }
}

/// The passes section by section over every channel of a row (any number of sections),
/// fused or not (unfused, the operations of [`Sos::filtfilt`](super::Sos::filtfilt)),
/// over the rows, from the states and handing on the states of `forward`.
#[inline(always)]
fn by_section<const FUSED: bool>(
    sections: &[[f64; 6]],
    zi: &[[f64; 2]],
    ext: &mut [f64],
    g: usize,
    forward: &mut Forward<'_>,
) {
    let rows = ext.len() / g;
    let from = forward.from.min(rows);
    if from == rows {
        return;
    }
    let ns = sections.len();
    let mut z0 = vec![0.0; ns * g];
    let mut z1 = vec![0.0; ns * g];
    let init = |z0: &mut [f64], z1: &mut [f64], row: &[f64]| {
        for (s, z) in zi.iter().enumerate() {
            for c in 0..g {
                z0[s * g + c] = z[0] * row[c];
                z1[s * g + c] = z[1] * row[c];
            }
        }
    };
    let step = |z0: &mut [f64], z1: &mut [f64], row: &mut [f64]| {
        for (s, sec) in sections.iter().enumerate() {
            let z0 = &mut z0[s * g..(s + 1) * g];
            let z1 = &mut z1[s * g..(s + 1) * g];
            for ((x, p), q) in row.iter_mut().zip(z0.iter_mut()).zip(z1.iter_mut()) {
                *x = section::<FUSED>(sec, *x, p, q);
            }
        }
    };
    match forward.start {
        Some(start) => {
            for c in 0..g {
                for s in 0..ns {
                    [z0[s * g + c], z1[s * g + c]] = start[c * ns + s];
                }
            }
        }
        None => init(&mut z0, &mut z1, &ext[from * g..(from + 1) * g]),
    }
    let cut = forward.hand.as_ref().map(|(r, _)| (*r).max(from));
    let mut hand = |z0: &[f64], z1: &[f64]| {
        if let Some((_, out)) = forward.hand.as_mut() {
            for c in 0..g {
                for s in 0..ns {
                    out[c * ns + s] = [z0[s * g + c], z1[s * g + c]];
                }
            }
        }
    };
    for (r, row) in ext.chunks_exact_mut(g).enumerate().skip(from) {
        if cut == Some(r) {
            hand(&z0, &z1);
        }
        step(&mut z0, &mut z1, row);
    }
    if cut.is_some_and(|c| c >= rows) {
        hand(&z0, &z1);
    }
    init(&mut z0, &mut z1, &ext[(rows - 1) * g..]);
    for row in ext[from * g..].chunks_exact_mut(g).rev() {
        step(&mut z0, &mut z1, row);
    }
}

/// One sample `x` through one section `[b0, b1, b2, 1, a1, a2]` in transposed direct form
/// II with the states `p`, `q`: the filtered sample. Fused, each state's update rounds
/// once per operation pair.
#[inline(always)]
fn section<const FUSED: bool>(section: &[f64; 6], x: f64, p: &mut f64, q: &mut f64) -> f64 {
    let [b0, b1, b2, _, a1, a2] = *section;
    if FUSED {
        let out = b0.mul_add(x, *p);
        *p = b1.mul_add(x, (-a1).mul_add(out, *q));
        *q = b2.mul_add(x, -a2 * out);
        out
    } else {
        let out = b0 * x + *p;
        *p = b1 * x - a1 * out + *q;
        *q = b2 * x - a2 * out;
        out
    }
}

/// [`section`] fused for a section whose numerator is `[1, 2, 1]`, the same values to the
/// bit: a multiplication by 1 and a fused operation with one of its factors 1 round as the
/// addition alone, and `2 x` is exact (but where it overflows, beyond 8.9e307), so two
/// of the five multiplications go and two fused operations become additions, which this
/// processor's adders take beside its multipliers (the passes are bound by the
/// multipliers' throughput: docs/performance.md#streaming-identification).
#[inline(always)]
fn section_unit(section: &[f64; 6], x: f64, p: &mut f64, q: &mut f64) -> f64 {
    let [_, _, _, _, a1, a2] = *section;
    let out = x + *p;
    *p = (-a1).mul_add(out, *q) + (x + x);
    *q = x + -a2 * out;
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::{butterworth, chebyshev1};

    /// The passes without packing the kept rows.
    fn passes_from(
        sections: &[[f64; 6]],
        zi: &[[f64; 2]],
        ext: &mut [f64],
        g: usize,
        kept: Kept,
        forward: Forward<'_>,
    ) {
        passes_taking(sections, zi, ext, g, kept, forward, None);
    }

    /// The passes' signature, of every instance.
    type Passes = for<'a> fn(&[[f64; 6]], &[[f64; 2]], &mut [f64], usize, Kept, Forward<'a>);

    /// Every instance of the passes this processor has, named.
    fn instances() -> Vec<(&'static str, Passes)> {
        let mut instances: Vec<(&str, Passes)> = vec![("dispatched", passes_from)];
        #[cfg(target_arch = "x86_64")]
        {
            if crate::trig::vector_available() {
                // SAFETY: the CPU has AVX2 and FMA
                instances.push(("avx2", |s, z, e, g, k, mut f| unsafe {
                    passes_avx2(s, z, e, g, k, &mut f, &mut None);
                }));
            }
            if std::is_x86_feature_detected!("avx512f") && crate::trig::vector_available() {
                // SAFETY: the CPU has AVX-512F, AVX2 and FMA
                instances.push(("avx512", |s, z, e, g, k, mut f| unsafe {
                    passes_avx512(s, z, e, g, k, &mut f, &mut None);
                }));
            }
        }
        instances
    }

    /// A block of `rows x g` channels of different sines and offsets.
    fn block(rows: usize, g: usize) -> Vec<f64> {
        (0..rows * g)
            .map(|i| {
                let (r, c) = ((i / g) as f64, (i % g) as f64);
                (0.01 * r * (c + 1.0)).sin() + 0.3 * (0.37 * r + c).cos() + c
            })
            .collect()
    }

    /// Each instance this processor has filters every channel as the fused passes
    /// section by section do, to the bit, whatever the number of channels (full and
    /// partial lanes), of rows (tiles cut anywhere) and of sections; and the unfused
    /// passes to rounding.
    #[test]
    fn every_instance_filters_as_section_by_section() {
        let cascades = [
            chebyshev1(8, 0.05, 0.08).unwrap(),
            butterworth(2, 0.2).unwrap(),
            butterworth(5, 0.1).unwrap(),
            butterworth(6, 0.3).unwrap(),
            butterworth(10, 0.2).unwrap(),
        ];
        let instances = instances();
        let fused_dispatch = cfg!(target_arch = "x86_64") && crate::trig::vector_available();
        for sos in &cascades {
            let (sections, zi) = (sos.sections(), sos.steady_state());
            for (rows, g) in [
                (3, 2),
                (700, 1),
                (700, 7),
                (2100, 32),
                (601, 13),
                (300, 202),
            ] {
                let x = block(rows, g);
                let mut fused = x.clone();
                by_section::<true>(sections, &zi, &mut fused, g, &mut Forward::whole());
                let mut plain = x.clone();
                by_section::<false>(sections, &zi, &mut plain, g, &mut Forward::whole());
                let scale = plain.iter().fold(1.0f64, |m, v| m.max(v.abs()));
                for (a, b) in fused.iter().zip(&plain) {
                    assert!((a - b).abs() < 1e-12 * scale, "{a} vs {b}");
                }
                for (name, f) in &instances {
                    let mut y = x.clone();
                    f(sections, &zi, &mut y, g, Kept::ALL, Forward::whole());
                    let expected = if *name == "dispatched" && !fused_dispatch {
                        &plain
                    } else {
                        &fused
                    };
                    assert!(
                        y == *expected,
                        "{name}, {} sections, {rows} rows of {g} channels",
                        sections.len()
                    );
                    // the rows a decimation keeps are the same when only they are stored
                    for kept in [
                        Kept {
                            every: 10,
                            first: 3,
                        },
                        Kept { every: 3, first: 0 },
                    ] {
                        let mut y = x.clone();
                        f(sections, &zi, &mut y, g, kept, Forward::whole());
                        for r in (kept.first..rows).step_by(kept.every) {
                            assert!(
                                y[r * g..(r + 1) * g] == expected[r * g..(r + 1) * g],
                                "{name}, {kept:?}, row {r} of {rows}, {g} channels"
                            );
                        }
                    }
                }
            }
        }
    }

    /// A record filtered in two calls, the forward states of the first handed to the
    /// second (which starts there), gives the whole record's values to the bit from that
    /// row on, with every instance and section by section, fused or not; handing the
    /// states on changes nothing of the first call's values. Also with the states handed
    /// on after the last row, and rows kept by a decimation.
    #[test]
    fn forward_states_handed_on_continue_the_record() {
        let cascades = [
            chebyshev1(8, 0.05, 0.08).unwrap(),
            butterworth(2, 0.2).unwrap(),
            butterworth(10, 0.2).unwrap(),
        ];
        let mut all = instances();
        all.push(("by section, fused", |s, z, e, g, _, mut f| {
            by_section::<true>(s, z, e, g, &mut f)
        }));
        all.push(("by section", |s, z, e, g, _, mut f| {
            by_section::<false>(s, z, e, g, &mut f)
        }));
        for sos in &cascades {
            let (sections, zi) = (sos.sections(), sos.steady_state());
            let ns = sections.len();
            for (rows, g, at, ahead) in [
                (700, 1, 300, 100),
                (2100, 32, 1000, 500),
                (601, 13, 200, 400),
                (300, 202, 150, 150),
                (500, 7, 0, 300),
            ] {
                let x = block(rows, g);
                for (name, f) in &all {
                    for kept in [
                        Kept::ALL,
                        Kept {
                            every: 10,
                            first: 3,
                        },
                    ] {
                        let what =
                            format!("{name}, {ns} sections, {rows} x {g}, at {at}, {kept:?}");
                        let mut whole = x.clone();
                        f(sections, &zi, &mut whole, g, kept, Forward::whole());
                        // the first part: the record up to `at + ahead`, its states at `at`
                        let first_rows = (at + ahead).min(rows);
                        let mut states = vec![[f64::NAN; 2]; g * ns];
                        let mut first = x[..first_rows * g].to_vec();
                        f(
                            sections,
                            &zi,
                            &mut first,
                            g,
                            kept,
                            Forward {
                                from: 0,
                                start: None,
                                hand: Some((at, &mut states)),
                            },
                        );
                        let mut alone = x[..first_rows * g].to_vec();
                        f(sections, &zi, &mut alone, g, kept, Forward::whole());
                        assert!(first == alone, "{what}: handing on changed the values");
                        assert!(states.iter().flatten().all(|v| v.is_finite()), "{what}");
                        let mut second = x.clone();
                        f(
                            sections,
                            &zi,
                            &mut second,
                            g,
                            kept,
                            Forward {
                                from: at,
                                start: Some(&states),
                                hand: None,
                            },
                        );
                        assert!(
                            second[..at * g] == x[..at * g],
                            "{what}: rows before `from`"
                        );
                        for r in
                            (at..rows).filter(|r| kept.every == 1 || r % kept.every == kept.first)
                        {
                            assert!(
                                second[r * g..(r + 1) * g] == whole[r * g..(r + 1) * g],
                                "{what}: row {r}"
                            );
                        }
                        // handed on after the last row: the states a next block starts from
                        let mut end = vec![[f64::NAN; 2]; g * ns];
                        let mut y = x.clone();
                        f(
                            sections,
                            &zi,
                            &mut y,
                            g,
                            kept,
                            Forward {
                                from: 0,
                                start: None,
                                hand: Some((rows, &mut end)),
                            },
                        );
                        assert!(end.iter().flatten().all(|v| v.is_finite()), "{what}");
                    }
                }
            }
        }
    }

    /// A block padded with channels of zeros to [`padded_width`] filters its own channels
    /// to the bit as the block alone does, the zeros stay zeros, and the padded width is a
    /// whole number of the processor's lanes (or the block's own width).
    #[test]
    fn channels_of_zeros_change_nothing() {
        for sos in [
            chebyshev1(8, 0.05, 0.08).unwrap(),
            butterworth(4, 0.04).unwrap(),
            butterworth(10, 0.2).unwrap(),
        ] {
            let (sections, zi) = (sos.sections(), sos.steady_state());
            let lane = lane_width(sections.len());
            for (rows, g) in [
                (700, 7),
                (601, 13),
                (300, 10),
                (500, 3),
                (400, 16),
                (300, 1),
            ] {
                let width = padded_width(g, sections.len());
                assert!(
                    width == g || (width > g && width.is_multiple_of(8)),
                    "{g} -> {width}"
                );
                assert!(
                    lane == 1 || g == 1 || width.is_multiple_of(8),
                    "{g} -> {width}"
                );
                let x = block(rows, g);
                let mut alone = x.clone();
                passes_from(sections, &zi, &mut alone, g, Kept::ALL, Forward::whole());
                let mut padded: Vec<f64> = x
                    .chunks_exact(g)
                    .flat_map(|r| r.iter().copied().chain(std::iter::repeat_n(0.0, width - g)))
                    .collect();
                passes_from(
                    sections,
                    &zi,
                    &mut padded,
                    width,
                    Kept::ALL,
                    Forward::whole(),
                );
                for (a, b) in alone.chunks_exact(g).zip(padded.chunks_exact(width)) {
                    assert!(a == &b[..g], "{rows} x {g} padded to {width}");
                    assert!(b[g..].iter().all(|v| *v == 0.0), "{rows} x {g}");
                }
            }
        }
    }

    /// The rows the backward pass keeps, stored into a [`Take`] instead of the block: the
    /// same values to the bit as it leaves in the block, the kept rows outside the taken
    /// ones left in the block; with a partial lane, one channel or no lanes on this
    /// processor they all stay in the block, and `passes_taking` says so.
    #[test]
    fn kept_rows_taken_are_those_left_in_the_block() {
        let kept = Kept {
            every: 10,
            first: 3,
        };
        for sos in [
            chebyshev1(8, 0.05, 0.08).unwrap(),
            butterworth(2, 0.2).unwrap(),
            butterworth(10, 0.2).unwrap(),
        ] {
            let (sections, zi) = (sos.sections(), sos.steady_state());
            let ns = sections.len();
            for (rows, g) in [
                (700, 16),
                (2100, 32),
                (601, 13),
                (300, 8),
                (500, 1),
                (333, 7),
            ] {
                let x = block(rows, g);
                let mut whole = x.clone();
                passes_from(sections, &zi, &mut whole, g, kept, Forward::whole());
                let lanes = lane_width(ns) > 1 && g > 1 && padded_width(g, ns) == g;
                // the decimation's: the rows between pads, packed at the end
                let (pad, end) = (23, rows - 30);
                let packed = |t: std::ops::Range<usize>| {
                    let at = rows - t.len().div_ceil(10);
                    Take { rows: t, at }
                };
                for take in [
                    packed(pad..end),
                    packed(3..rows),
                    packed(13..rows - 7),
                    packed(23..24),
                    Take { rows: 3..3, at: 0 },
                    // the fewest rows ahead of each: row at + i is row 3 + 10 i's ninth
                    // successor
                    Take {
                        rows: 3..rows - 30,
                        at: 3 + ((rows - 33).div_ceil(10) - 1) * 9,
                    },
                ] {
                    let mut y = x.clone();
                    let took = passes_taking(
                        sections,
                        &zi,
                        &mut y,
                        g,
                        kept,
                        Forward::whole(),
                        Some(take.clone()),
                    );
                    let what = format!("{ns} sections, {rows} x {g}, {take:?}");
                    assert_eq!(took, lanes, "{what}");
                    for (i, r) in take.rows.clone().step_by(10).enumerate() {
                        let at = if took { take.at + i } else { r };
                        assert!(
                            y[at * g..(at + 1) * g] == whole[r * g..(r + 1) * g],
                            "{what}: row {r}"
                        );
                    }
                    let packed = take.at..take.at + take.count(10);
                    for r in (3..rows)
                        .step_by(10)
                        .filter(|r| !(take.rows.contains(r) || took && packed.contains(r)))
                    {
                        assert!(
                            y[r * g..(r + 1) * g] == whole[r * g..(r + 1) * g],
                            "{what}: row {r} left at its place"
                        );
                    }
                }
            }
        }
    }
}
