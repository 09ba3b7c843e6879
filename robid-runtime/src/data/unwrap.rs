//! Angles logged modulo a turn: a continuous joint's position written in [-pi, pi), a
//! single-turn motor encoder. The dynamics see the same angle, but the velocities and
//! accelerations differentiated from it see a jump of a whole turn in one sample (a log
//! wrapped so was fitted to 42 % with exit 0, the only word a speed "faster than 64 rad/s"
//! blamed on the time's unit, and `inspect` called the joint at rest). The loader
//! unwraps such columns as it reads them, before any interpolation, and says so.

use std::path::Path;

use super::config::{AngleUnit, Config};
use super::load::ROLES;
use super::time::Warning;

/// A step between two samples is taken for a wrap when it lies within this share of a
/// turn of a nonzero whole number of turns: a joint turning an eighth of a turn in one
/// sample (785 rad/s at 1 kHz) does not exist, and a step near half a turn is left as it
/// is, being ambiguous.
pub const WRAP_TOLERANCE: f64 = 0.125;

/// The roles whose columns are angles that may wrap: the positions (of revolute joints)
/// and the motor encoders.
const ANGLE_ROLES: [&str; 2] = ["position", "motor_position"];

/// The unwrapping state of a record's angle columns, carried from one window of rows to
/// the next.
#[derive(Debug, Clone)]
pub(crate) struct Unwrap {
    /// One turn in the file's angle unit.
    turn: f64,
    /// Per role and joint: whether the column is an angle.
    angle: Vec<bool>,
    /// Per role and joint: the last value read, as read.
    last: Vec<Option<f64>>,
    /// Per role and joint: the whole turns added so far.
    offset: Vec<f64>,
    /// Per role and joint: the wraps found, and the file line of the first.
    wraps: Vec<(usize, u64)>,
    dof: usize,
}

impl Unwrap {
    /// The state before the first row of a record of `dof` joints read with `config`
    /// (its angle unit, and which joints are prismatic).
    pub(crate) fn new(config: &Config, dof: usize) -> Self {
        let turn = match config.units.angle {
            AngleUnit::Rad => std::f64::consts::TAU,
            AngleUnit::Deg => 360.0,
        };
        let angle = ROLES
            .iter()
            .flat_map(|role| {
                (0..dof).map(move |j| {
                    let prismatic = config.prismatic.get(j).copied().unwrap_or(false);
                    ANGLE_ROLES.contains(role) && !(prismatic && *role == "position")
                })
            })
            .collect();
        let cells = ROLES.len() * dof;
        Self {
            turn,
            angle,
            last: vec![None; cells],
            offset: vec![0.0; cells],
            wraps: vec![(0, 0); cells],
            dof,
        }
    }

    /// Unwraps the angle columns among `columns`, whose role `r` starts at column
    /// `start` for each `(r, start)` of `spans`; row k is the file's line `lines[k]`.
    pub(crate) fn apply(
        &mut self,
        spans: &[(usize, usize)],
        columns: &mut [Vec<f64>],
        lines: &[u64],
    ) {
        for &(role, start) in spans {
            for j in 0..self.dof {
                let cell = role * self.dof + j;
                if !self.angle[cell] {
                    continue;
                }
                let Some(x) = columns.get_mut(start + j) else {
                    continue;
                };
                let half = 0.5 * self.turn;
                for (k, v) in x.iter_mut().enumerate() {
                    let read = *v;
                    // (a step below half a turn, every step of a log that does not
                    // wrap, is no wrap: one comparison per sample)
                    if let Some(last) = self.last[cell].filter(|l| (read - l).abs() > half) {
                        let turns = ((read - last) / self.turn).round();
                        let off = (read - last - turns * self.turn).abs();
                        if turns != 0.0
                            && off <= WRAP_TOLERANCE * self.turn
                            && self.in_one_turn(last)
                            && self.in_one_turn(read)
                        {
                            self.offset[cell] -= turns * self.turn;
                            let (count, first) = &mut self.wraps[cell];
                            if *count == 0 {
                                *first = lines.get(k).copied().unwrap_or_default();
                            }
                            *count += 1;
                        }
                    }
                    self.last[cell] = Some(read);
                    *v = read + self.offset[cell];
                }
            }
        }
    }

    /// Whether `v` lies where a wrapped angle lies, in [-half a turn, half a turn] or
    /// [0, a turn] (to rounding): a multi-turn encoder's angle, which a fast motor turns
    /// by whole turns between slow samples, does not stay there.
    fn in_one_turn(&self, v: f64) -> bool {
        let edge = self.turn * (1.0 + 1e-9);
        v.abs() <= 0.5 * edge || (0.0..=edge).contains(&v)
    }

    /// A warning per column of the file at `path` that wrapped.
    pub(crate) fn warnings(&self, path: &Path) -> Vec<Warning> {
        (self.wraps.iter().enumerate())
            .filter(|(_, (count, _))| *count > 0)
            .map(|(cell, &(wraps, first_line))| Warning::Unwrapped {
                path: path.to_path_buf(),
                role: ROLES[cell / self.dof],
                joint: cell % self.dof + 1,
                wraps,
                first_line,
                turn: self.turn,
            })
            .collect()
    }
}

/// The text of [`Warning::Unwrapped`].
pub(crate) fn unwrapped_text(
    path: &Path,
    role: &str,
    joint: usize,
    wraps: usize,
    first_line: u64,
    turn: f64,
) -> String {
    let what = if role == "position" {
        format!("joint {joint}'s positions")
    } else {
        format!("joint {joint}'s motor positions")
    };
    format!(
        "{}: {what} jump by a whole turn ({}) between two rows {} (the first at line \
         {first_line}): an angle logged modulo a turn (a continuous joint, a single-turn \
         encoder); unwrapped, each jump taken out, so that the velocities and accelerations \
         see the motion",
        path.display(),
        crate::Num(turn),
        crate::Count(wraps, "time")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A joint turning at 2 rad/s sampled at 100 Hz, logged in [-pi, pi), read in two
    /// windows: unwrapped to the turning angle, each wrap counted once with its line; a
    /// prismatic joint's and a velocity column's steps are left alone, and so is a step
    /// of half a turn.
    #[test]
    fn wraps_are_taken_out_across_windows() {
        let pi = std::f64::consts::PI;
        let config = Config {
            prismatic: vec![false, true],
            ..Config::default()
        };
        let mut unwrap = Unwrap::new(&config, 2);
        let n = 1000;
        let truth: Vec<f64> = (0..n).map(|k| 2.0 * k as f64 * 0.01 - 3.0).collect();
        let wrapped: Vec<f64> = truth
            .iter()
            .map(|a| (a + pi).rem_euclid(2.0 * pi) - pi)
            .collect();
        let jumpy: Vec<f64> = (0..n)
            .map(|k| if k % 2 == 0 { 0.0 } else { 2.0 * pi })
            .collect();
        let mut out = Vec::new();
        // columns: qd1, qd2, q1, q2 (prismatic)
        for window in [0..400, 400..n] {
            let mut columns = vec![
                jumpy[window.clone()].to_vec(),
                jumpy[window.clone()].to_vec(),
                wrapped[window.clone()].to_vec(),
                jumpy[window.clone()].to_vec(),
            ];
            let lines: Vec<u64> = window.clone().map(|k| k as u64 + 2).collect();
            unwrap.apply(&[(1, 0), (0, 2)], &mut columns, &lines);
            for c in [0, 1, 3] {
                assert_eq!(columns[c][..], jumpy[window.clone()]);
            }
            out.extend_from_slice(&columns[2]);
        }
        let worst = out
            .iter()
            .zip(&truth)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12, "{worst}");
        let warnings = unwrap.warnings(Path::new("log.csv"));
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        // from -3 to 16.98 rad: wraps at pi, 3 pi and 5 pi, the first at sample 308
        // (line 310), the second in the second window
        let text = warnings[0].to_string();
        assert!(
            text.starts_with("log.csv: joint 1's positions jump by a whole turn (6.283185307179586) between two rows 3 times (the first at line 310)"),
            "{text}"
        );
        // half a turn is ambiguous: left as read
        let mut unwrap = Unwrap::new(&Config::default(), 1);
        let mut half = vec![vec![0.0, pi, 0.0]];
        unwrap.apply(&[(0, 0)], &mut half, &[2, 3, 4]);
        assert_eq!(half[0], [0.0, pi, 0.0]);
        assert!(unwrap.warnings(Path::new("log.csv")).is_empty());
        // the range a wrapped angle lies in, to rounding: -pi (written a little beyond it)
        // is in, a value beyond half a turn that is not in [0, a turn] is out
        let edge = -pi * (1.0 + 1e-10);
        let mut unwrap = Unwrap::new(&Config::default(), 1);
        let mut at_pi = vec![vec![-3.0, edge, edge + 2.0 * pi - 0.01]];
        unwrap.apply(&[(0, 0)], &mut at_pi, &[2, 3, 4]);
        assert!((at_pi[0][2] - (edge - 0.01)).abs() < 1e-12, "{at_pi:?}");
        let mut unwrap = Unwrap::new(&Config::default(), 1);
        let mut beyond = vec![vec![2.8, 2.8 - 2.0 * pi]];
        let read = beyond.clone();
        unwrap.apply(&[(0, 0)], &mut beyond, &[2, 3]);
        assert_eq!(beyond, read);
        // a single-turn motor encoder (joint 2's) is unwrapped, and named as such
        let mut unwrap = Unwrap::new(&Config::default(), 2);
        let mut motor = vec![vec![0.0; 3], vec![3.0, 3.1, 3.2 - 2.0 * pi]];
        unwrap.apply(&[(4, 0)], &mut motor, &[7, 8, 9]);
        assert!((motor[1][2] - 3.2).abs() < 1e-12, "{motor:?}");
        let warnings = unwrap.warnings(Path::new("log.csv"));
        assert!(
            matches!(
                warnings[..],
                [Warning::Unwrapped {
                    role: "motor_position",
                    joint: 2,
                    ..
                }]
            ),
            "{warnings:?}"
        );
        let w = warnings[0].to_string();
        assert!(
            w.contains("joint 2's motor positions jump") && w.contains("line 9"),
            "{w}"
        );
        // a multi-turn motor encoder sampled slowly: whole turns between samples are motion
        let mut unwrap = Unwrap::new(&Config::default(), 1);
        let mut turning = vec![vec![40.0, 40.0 + 2.0 * pi, 40.0 + 4.0 * pi + 0.1]];
        let read = turning.clone();
        unwrap.apply(&[(4, 0)], &mut turning, &[2, 3, 4]);
        assert_eq!(turning, read);
        // degrees: a turn of 360
        let mut config = Config::default();
        config.units.angle = AngleUnit::Deg;
        let mut unwrap = Unwrap::new(&config, 1);
        let mut degrees = vec![vec![170.0, 178.0, -174.0, -166.0]];
        unwrap.apply(&[(0, 0)], &mut degrees, &[2, 3, 4, 5]);
        assert_eq!(degrees[0], [170.0, 178.0, 186.0, 194.0]);
    }
}
