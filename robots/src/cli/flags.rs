//! Checks of command-line values, as clap value parsers: a value outside its documented
//! range is refused before any work, and clap names the flag in the message
//! (`invalid value '0' for '--sigma <SIGMA>': 0 is outside [1e-9, 1e6] N m`).
//!
//! The ranges are in each flag's `--help` text and in README.md ("Using robid").

use std::fmt;

use robid_runtime::{Count, num};

use super::Error;

/// The most samples `robid excite` writes (`--duration` x `--rate`): a million rows of
/// `t,q,qd,qdd` (e.g. 1000 s at 1 kHz), about 180 MB in memory for seven joints.
pub(crate) const MAX_SAMPLES: f64 = 1e6;

/// A range of real numbers `lo..=hi` (`lo` excluded when `open`; 0 also accepted when
/// `zero`; the negatives of the range too when `signed`), in `unit`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Range {
    lo: f64,
    hi: f64,
    open: bool,
    zero: bool,
    signed: bool,
    unit: &'static str,
}

impl fmt::Display for Range {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let open = if self.open { '(' } else { '[' };
        if self.zero {
            write!(f, "0 or ")?;
        }
        if self.signed {
            let close = if self.open { ')' } else { ']' };
            write!(f, "[{}, {}{close} or ", short(-self.hi), short(-self.lo))?;
        }
        write!(f, "{open}{}, {}]", short(self.lo), short(self.hi))?;
        if !self.unit.is_empty() {
            write!(f, " {}", self.unit)?;
        }
        Ok(())
    }
}

/// `x` as people write limits: `0`, `0.5`, `200`, `1e6`, `1e-9`. Not
/// `robid_runtime::Num`, which writes a value as typed (`1000000` for 1e6, plain up to
/// 1e15): the ranges in messages must read as in each flag's `--help` and the docs
/// (`[0, 1e6] N m`).
pub(crate) fn short(x: f64) -> String {
    if x == 0.0 || (1e-3..1e4).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

impl Range {
    fn contains(&self, x: f64) -> bool {
        let x = if self.signed { x.abs() } else { x };
        (self.zero && x == 0.0)
            || (if self.open { x > self.lo } else { x >= self.lo }) && x <= self.hi
    }

    /// Parses one value.
    fn parse(&self, text: &str) -> Result<f64, String> {
        let x: f64 = text
            .trim()
            .parse()
            .map_err(|_| format!("`{text}` is not a number; write a decimal number such as 0.5"))?;
        let text = text.trim();
        if !x.is_finite() {
            return Err(format!(
                "{text} is not a finite number; give a value in {self}"
            ));
        }
        if !self.contains(x) {
            return Err(format!("{text} is outside {self}"));
        }
        Ok(x)
    }
}

/// Real numbers in `[lo, hi]`, in `unit`.
pub(crate) const fn closed(lo: f64, hi: f64, unit: &'static str) -> Range {
    Range {
        lo,
        hi,
        open: false,
        zero: false,
        signed: false,
        unit,
    }
}

/// Real numbers of either sign whose magnitude is in `[lo, hi]`, in `unit`: a factor whose
/// sign is the wiring's (a torque constant of a motor wired the other way round).
pub(crate) const fn either_sign(lo: f64, hi: f64, unit: &'static str) -> Range {
    Range {
        signed: true,
        ..closed(lo, hi, unit)
    }
}

/// 0, or real numbers in `[lo, hi]`, in `unit`: a setting that 0 turns off, and that a
/// positive value below `lo` would break rather than turn off (an encoder resolution of
/// 1e-320 rad overflows `q / resolution`).
pub(crate) const fn zero_or(lo: f64, hi: f64, unit: &'static str) -> Range {
    Range {
        lo,
        hi,
        open: false,
        zero: true,
        signed: false,
        unit,
    }
}

/// Real numbers in `(0, hi]`, in `unit`.
pub(crate) const fn positive(hi: f64, unit: &'static str) -> Range {
    Range {
        lo: 0.0,
        hi,
        open: true,
        zero: false,
        signed: false,
        unit,
    }
}

/// The clap value parser of `range`.
pub(crate) fn real(
    range: Range,
) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync + 'static {
    move |text| range.parse(text)
}

/// The clap value parser of whole numbers in `lo..=hi`.
pub(crate) fn count(
    lo: usize,
    hi: usize,
) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync + 'static {
    move |text| {
        let n: usize = text
            .trim()
            .parse()
            .map_err(|_| format!("`{text}` is not a whole number; give one in {lo}..={hi}"))?;
        if !(lo..=hi).contains(&n) {
            return Err(format!("{n} is outside {lo}..={hi}"));
        }
        Ok(n)
    }
}

/// The clap value parser of a random generator's seed: any whole number from 0 to
/// 2^64 - 1, with the same message as [`count`]'s (clap's own says only "invalid digit").
pub(crate) fn seed(text: &str) -> Result<u64, String> {
    text.trim().parse().map_err(|_| {
        format!(
            "`{text}` is not a whole number; give one in 0..={}",
            u64::MAX
        )
    })
}

/// The fewest samples of a trajectory `robid excite` writes: both ends, at rest, and one
/// between (`robid_runtime::excite`'s sampling asks for as many).
pub(crate) const MIN_SAMPLES: f64 = 3.0;

/// Refuses a sampling of `duration` s at `rate` Hz (t = 0, 1/rate, .., duration: the
/// rounded product plus one samples) with more than [`MAX_SAMPLES`] samples, before
/// anything is allocated, or with fewer than [`MIN_SAMPLES`], before the design is
/// optimised for a trajectory that cannot be written.
pub(crate) fn check_samples(duration: f64, rate: f64) -> Result<(), Error> {
    let samples = duration * rate;
    let (d, r) = (num(duration), num(rate));
    if !(samples.is_finite() && samples <= MAX_SAMPLES) {
        return Err(format!(
            "--duration {d} s at --rate {r} Hz gives {} samples, more than the limit of \
             {MAX_SAMPLES:e}; shorten --duration or lower --rate",
            short(samples)
        )
        .into());
    }
    let count = samples.round() + 1.0;
    if count < MIN_SAMPLES {
        return Err(format!(
            "--duration {d} s at --rate {r} Hz gives {} (t = 0, 1 / rate, .., \
             duration), fewer than the {MIN_SAMPLES} a trajectory needs; lengthen --duration \
             or raise --rate so that their product is at least 2",
            // below MIN_SAMPLES: 1 or 2
            Count(count as usize, "sample")
        )
        .into());
    }
    // t = 0, 1 / rate, .., duration: a duration that is no whole number of sample periods
    // ended a sample period past it (Fourier: off rest) or short of it (still moving)
    if !whole(samples) {
        let (lo, hi) = (samples.floor(), samples.ceil());
        let rates = if lo >= MIN_SAMPLES - 1.0 {
            format!("{} or {}", num(lo / duration), num(hi / duration))
        } else {
            num(hi / duration)
        };
        let durations = if lo >= MIN_SAMPLES - 1.0 {
            format!("{} or {}", num(lo / rate), num(hi / rate))
        } else {
            num(hi / rate)
        };
        return Err(format!(
            "--duration {d} s at --rate {r} Hz gives {} sample periods, not a whole number: \
             the samples (t = 0, 1 / rate, ..) would miss the end of the trajectory, where it \
             is at rest; choose --rate {rates} Hz, or --duration {durations} s",
            num(samples)
        )
        .into());
    }
    Ok(())
}

/// Whether `periods` (duration x rate) is a whole number, up to the rounding of the
/// product (0.3 s x 10 Hz is 3.0000000000000004).
pub(crate) fn whole(periods: f64) -> bool {
    (periods - periods.round()).abs() <= 1e-9 * periods.max(1.0)
}

/// Refuses `flag` when it was given but belongs to another method than `method`.
pub(crate) fn only_for(given: bool, flag: &str, owner: &str, method: &str) -> Result<(), Error> {
    if given {
        return Err(format!(
            "{flag} is an option of {owner}, not of {method}; drop {flag} or use {owner}"
        )
        .into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_refuse_what_lies_outside_and_say_why() {
        let p = real(positive(1e6, "Hz"));
        assert_eq!(p("500"), Ok(500.0));
        assert_eq!(p("1e6"), Ok(1e6));
        assert_eq!(p("0").unwrap_err(), "0 is outside (0, 1e6] Hz");
        assert!(p("1e9").unwrap_err().contains("outside (0, 1e6] Hz"));
        assert!(p("-1").unwrap_err().contains("outside"));
        assert!(p("nan").unwrap_err().contains("not a finite number"));
        assert!(p("inf").unwrap_err().contains("not a finite number"));
        assert!(p("fast").unwrap_err().contains("`fast` is not a number"));
        let c = real(closed(0.0, 1.0, "rad"));
        assert_eq!(c("0"), Ok(0.0));
        assert!(c("1.5").is_err());
        let n = count(2, 50);
        assert_eq!(n("2"), Ok(2));
        assert!(n("1").unwrap_err().contains("outside 2..=50"));
        assert!(n("51").is_err());
        assert!(n("-3").unwrap_err().contains("not a whole number"));
    }

    #[test]
    fn samples_are_checked_before_allocating() {
        assert!(check_samples(1000.0, 1000.0).is_ok());
        let e = check_samples(1e9, 500.0).unwrap_err().to_string();
        assert!(e.contains("--duration") && e.contains("--rate"), "{e}");
        assert!(check_samples(30.0, 1e9).is_err());
        assert!(check_samples(1e6, 1e6).is_err());
    }

    /// Fewer than three samples are refused here, before the design: the sampling after
    /// it refused them only once the optimisation had run (minutes with --method points).
    #[test]
    fn too_few_samples_are_refused_before_the_design() {
        assert!(check_samples(2.0, 1.0).is_ok());
        let e = check_samples(1.0, 1.0).unwrap_err().to_string();
        assert!(
            e.contains("--duration 1 s at --rate 1 Hz gives 2 samples")
                && e.contains("fewer than the 3 a trajectory needs"),
            "{e}"
        );
        let e = check_samples(1e-300, 500.0).unwrap_err().to_string();
        assert!(
            e.contains("--duration 1e-300 s at --rate 500 Hz gives 1 sample ("),
            "{e}"
        );
    }

    /// A duration that is no whole number of sample periods is refused, with the nearest
    /// rates and durations that are: `--duration 10 --rate 7.25` wrote 74 samples, the last
    /// at 10.069 s and off rest, and `--rate 7.24` 73, the last at 9.945 s, still moving.
    #[test]
    fn a_duration_of_no_whole_number_of_sample_periods_is_refused() {
        assert!(check_samples(0.3, 10.0).is_ok());
        assert!(check_samples(10.0, 7.2).is_ok());
        for (rate, told) in [
            (7.25, "gives 72.5 sample periods"),
            (7.24, "gives 72.4 sample periods"),
        ] {
            let e = check_samples(10.0, rate).unwrap_err().to_string();
            assert!(
                e.contains(&format!("--duration 10 s at --rate {rate} Hz {told}"))
                    && e.contains("choose --rate 7.2 or 7.3 Hz, or --duration "),
                "{e}"
            );
        }
        let e = check_samples(10.0, 7.25).unwrap_err().to_string();
        assert!(
            e.contains("--duration 9.931034482758621 or 10.068965517241379 s"),
            "{e}"
        );
    }
}
