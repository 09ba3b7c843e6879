//! The time at rest of each joint from its positions read block by block: the velocity is
//! [`Sos::filtfilt`] of the positions, differentiated by [`central_difference`], to the
//! bit, without the record in memory.
//!
//! A zero-phase filter runs forward over the whole record, then backward from its end, so
//! no block's output is known before the record's end has been filtered forward. The
//! forward pass is run once over the record keeping only its section states at each
//! block's start (a few numbers per joint and block); the blocks are then taken from the
//! last to the first, each filtered forward again from its state (the same operations, so
//! the same values) and backward from the state the later blocks left. The odd
//! extensions at both ends are [`Sos::filtfilt`]'s own (its `pad_length` samples).
//!
//! Each pass is [`Sos::pass`], the operations of [`Sos::filtfilt`] on this processor
//! carried from block to block.
//!
//! [`central_difference`]: crate::signal::central_difference

use crate::data::{Dataset, Record};
use crate::error::{Error, Result};
use crate::signal::Sos;

/// The section states of a cascade, each `[p, q]` of the transposed direct form II.
type State = Vec<[f64; 2]>;

/// The steady state of the cascade whose per-unit steady state is `zi`, for a constant
/// input `x` (where each pass starts).
fn steady(zi: &[[f64; 2]], x: f64) -> State {
    zi.iter().map(|z| [z[0] * x, z[1] * x]).collect()
}

/// Per joint, the samples of `data` whose velocity (the positions through `sos` forward
/// and backward, then central differences) is below `rest[j]` in magnitude, reading
/// `block` samples at a time; `visit` is given every block of the forward pass, in order
/// (what else is counted). `data` needs more than `sos.pad_length()` samples.
pub(super) fn rest_counts(
    data: &dyn Record,
    sos: &Sos,
    rest: &[f64],
    block: usize,
    visit: impl FnMut(&Dataset),
) -> Result<Vec<usize>> {
    let mut counts = vec![0usize; data.dof()];
    velocities(data, sos, block, visit, |j, _, v| {
        counts[j] += v.iter().filter(|v| v.abs() < rest[j]).count();
    })?;
    Ok(counts)
}

/// The velocities of `data`: `each(j, k, v)` is given the velocities `v` of joint `j`
/// from sample `k` on, every sample once, from the last blocks to the first (see
/// [`rest_counts`]).
pub(super) fn velocities(
    data: &dyn Record,
    sos: &Sos,
    block: usize,
    mut visit: impl FnMut(&Dataset),
    mut each: impl FnMut(usize, usize, &[f64]),
) -> Result<()> {
    let (n, dof, dt) = (data.samples(), data.dof(), data.sample_time());
    let pad = sos.pad_length();
    if n <= pad {
        // too short: `Sos::filtfilt`'s own error
        sos.filtfilt(&data.read(0, n)?.q[0])?;
    }
    if pad == 0 {
        // every cascade with a section pads (a Butterworth low-pass has sections)
        return Err(Error::setting(
            "Sos",
            "sections",
            "a low-pass without sections filters nothing; design it with an order of 1 or more"
                .to_string(),
        ));
    }
    let block = block.max(1);
    let zi = sos.steady_state();
    // the odd extensions at both ends, as `Sos::filtfilt_extended` writes them
    let head = data.read(0, pad + 1)?;
    let tail = data.read(n - pad - 1, n)?;
    let front: Vec<Vec<f64>> = head
        .q
        .joints()
        .map(|x| (0..pad).map(|i| 2.0 * x[0] - x[pad - i]).collect())
        .collect();
    let back: Vec<Vec<f64>> = tail
        .q
        .joints()
        .map(|x| {
            // x holds samples n - pad - 1 ..= n - 1: x[pad] is the last
            (0..pad).map(|i| 2.0 * x[pad] - x[pad - 1 - i]).collect()
        })
        .collect();
    drop((head, tail));
    let starts: Vec<usize> = (0..n).step_by(block).collect();
    // the forward pass: each joint's state at each block's start
    let mut states: Vec<Vec<State>> = Vec::with_capacity(starts.len());
    let mut forward: Vec<State> = front.iter().map(|f| steady(&zi, f[0])).collect();
    for (f, s) in front.iter().zip(forward.iter_mut()) {
        sos.pass(s, &mut f.clone(), false);
    }
    for &start in &starts {
        states.push(forward.clone());
        let part = data.read(start, start + block)?;
        for (x, s) in part.q.joints().zip(forward.iter_mut()) {
            sos.pass(s, &mut x.to_vec(), false);
        }
        visit(&part);
    }
    // the back extension forward, then the backward pass from its last sample
    let mut backward: Vec<State> = Vec::with_capacity(dof);
    for (b, s) in back.iter().zip(forward.iter_mut()) {
        let mut b = b.clone();
        sos.pass(s, &mut b, false);
        let mut state = steady(&zi, b[pad - 1]);
        sos.pass(&mut state, &mut b, true);
        backward.push(state);
    }
    // the blocks from the last: filtered, then differentiated where both neighbours are
    // known; `later[j]` holds the first (up to) two filtered samples after the block
    let mut later: Vec<Vec<f64>> = vec![Vec::new(); dof];
    let mut v = Vec::with_capacity(block.min(n));
    let h = 0.5 / dt;
    for (&start, state) in starts.iter().zip(states).rev() {
        let part = data.read(start, start + block)?;
        for (j, (x, mut s)) in part.q.joints().zip(state).enumerate() {
            let mut y = x.to_vec();
            sos.pass(&mut s, &mut y, false);
            sos.pass(&mut backward[j], &mut y, true);
            let len = y.len();
            y.extend_from_slice(&later[j]);
            // sample start + k for k in 1..=len, where it exists (central_difference)
            v.clear();
            v.extend((1..=len.min(n - 1 - start)).map(|k| {
                if start + k == n - 1 {
                    (y[k] - y[k - 1]) / dt
                } else {
                    (y[k + 1] - y[k - 1]) * h
                }
            }));
            each(j, start + 1, &v);
            if start == 0 {
                each(j, 0, &[(y[1] - y[0]) / dt]);
            }
            y.truncate(2);
            later[j] = y;
        }
    }
    Ok(())
}
