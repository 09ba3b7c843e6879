//! The progress of long steps on standard error (docs/command-line.md#progress): an
//! indicatif bar when standard error is a terminal; anywhere else (a file, a pipe, `nohup`,
//! CI) one plain line every [`INTERVAL`] of wall time, such as
//!
//! ```text
//! excite: point design 40 % (120/300 evaluations), 21 s
//! ```
//!
//! without control characters, and nothing at all for a step that ends within the first
//! interval. Shown only when asked for: the library settings that ask for it
//! (`FourierDesign::progress`, `PointDesign::progress`, `AnnealOptions::progress`) are
//! false by default, and the command line sets them.
//!
//! Cheap where it is called most: the count is one shared atomic, but a hot loop ticks
//! through a [`Counter`], which gathers [`STRIDE`] calls before it touches the shared
//! count, the clock or the bar (indicatif reads the clock on every update).
//! [`Progress::add`] reads the clock on every call: it is for steps of milliseconds or
//! more (a restart, a joint's fit).

use std::cell::Cell;
use std::fmt;
use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Wall time before the first line off a terminal, and at least between two lines.
pub const INTERVAL: Duration = Duration::from_secs(10);

/// Calls a [`Counter`] gathers before it passes them on (and the clock is read).
pub const STRIDE: u32 = 64;

/// The progress of one step of `total` units; see the module docs.
///
/// ```
/// use robid_runtime::progress::Progress;
/// // `true` on the command line; a library call keeps it silent with `false`
/// let progress = Progress::new(false, "fit", 3, "joints");
/// for _joint in 0..3 {
///     // .. a fit of seconds ..
///     progress.tick();
/// }
/// progress.finish();
/// ```
pub struct Progress {
    shown: Option<Shown>,
}

/// What an enabled [`Progress`] holds.
struct Shown {
    title: String,
    total: u64,
    unit: &'static str,
    done: AtomicU64,
    view: View,
}

/// Where it is shown.
enum View {
    /// On a terminal.
    Bar(ProgressBar),
    /// Anywhere else.
    Lines(Mutex<Lines>),
}

/// The lines off a terminal: when the next may be written, and where.
struct Lines {
    /// Wall time since the step began.
    clock: Box<dyn FnMut() -> Duration + Send>,
    out: Box<dyn Write + Send>,
    /// No line before this time.
    next: Duration,
}

impl fmt::Debug for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.shown {
            None => f.write_str("Progress(hidden)"),
            Some(s) => f
                .debug_struct("Progress")
                .field("title", &s.title)
                .field("done", &s.done.load(Ordering::Relaxed))
                .field("total", &s.total)
                .field("unit", &s.unit)
                .field("bar", &matches!(s.view, View::Bar(_)))
                .finish(),
        }
    }
}

impl Progress {
    /// A step of `total` `unit`s (`300, "evaluations"`) titled `title` (`"excite: point
    /// design"`), shown on standard error when `enabled`: a bar on a terminal, else a line
    /// every [`INTERVAL`]. Disabled, it shows nothing and a tick costs a branch.
    pub fn new(enabled: bool, title: impl Into<String>, total: u64, unit: &'static str) -> Self {
        if !enabled {
            return Self { shown: None };
        }
        let title = title.into();
        let view = if std::io::stderr().is_terminal() {
            let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template("{msg} [{bar:40}] {percent}% {elapsed}")
            {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_message(title.clone());
            View::Bar(bar)
        } else {
            let start = Instant::now();
            View::Lines(Mutex::new(Lines {
                clock: Box::new(move || start.elapsed()),
                out: Box::new(std::io::stderr()),
                next: INTERVAL,
            }))
        };
        Self::shown(title, total, unit, view)
    }

    /// Lines to `out` at the times `clock` gives (the wall time since the step began),
    /// whatever standard error is: the tests' clock and writer.
    #[cfg(test)]
    fn to_lines(
        title: &str,
        total: u64,
        unit: &'static str,
        clock: impl FnMut() -> Duration + Send + 'static,
        out: impl Write + Send + 'static,
    ) -> Self {
        let lines = Lines {
            clock: Box::new(clock),
            out: Box::new(out),
            next: INTERVAL,
        };
        Self::shown(
            title.to_owned(),
            total,
            unit,
            View::Lines(Mutex::new(lines)),
        )
    }

    fn shown(title: String, total: u64, unit: &'static str, view: View) -> Self {
        Self {
            shown: Some(Shown {
                title,
                total,
                unit,
                done: AtomicU64::new(0),
                view,
            }),
        }
    }

    /// `n` units done (`0`: none, but a line may be due). Reads the clock: for steps of
    /// milliseconds or more; a hot loop ticks through a [`Counter`].
    pub fn add(&self, n: u64) {
        let Some(s) = &self.shown else {
            return;
        };
        let done = s.done.fetch_add(n, Ordering::Relaxed).saturating_add(n);
        match &s.view {
            View::Bar(bar) => bar.set_position(done),
            // a thread that finds another one writing leaves the line to it
            View::Lines(lines) => {
                if let Ok(mut lines) = lines.try_lock() {
                    lines.report(s);
                }
            }
        }
    }

    /// One unit done (as [`Progress::add`]).
    pub fn tick(&self) {
        self.add(1);
    }

    /// A counter for one thread's hot loop (see [`Counter`]).
    pub fn counter(&self) -> Counter<'_> {
        Counter {
            progress: self,
            pending: Cell::new(0),
            calls: Cell::new(0),
        }
    }

    /// Removes the bar (as dropping does); writes nothing more.
    pub fn finish(self) {}
}

impl Drop for Progress {
    fn drop(&mut self) {
        if let Some(Shown {
            view: View::Bar(bar),
            ..
        }) = &self.shown
        {
            bar.finish_and_clear();
        }
    }
}

impl Lines {
    /// Writes the line of `s` if one is due; a line that cannot be written stops them.
    fn report(&mut self, s: &Shown) {
        let now = (self.clock)();
        if now < self.next {
            return;
        }
        self.next = now.saturating_add(INTERVAL);
        let done = s.done.load(Ordering::Relaxed);
        let line = line(&s.title, done, s.total, s.unit, now);
        if self.out.write_all(line.as_bytes()).is_err() {
            self.next = Duration::MAX;
        }
    }
}

/// `excite: point design 40 % (120/300 evaluations), 21 s` and a newline; the count is
/// held at the total (a minimisation may take a few evaluations more than its budget).
fn line(title: &str, done: u64, total: u64, unit: &str, elapsed: Duration) -> String {
    let time = wall_time(elapsed);
    if total == 0 {
        return format!("{title}: {done} {unit}, {time}\n");
    }
    let done = done.min(total);
    let percent = u128::from(done) * 100 / u128::from(total);
    format!("{title} {percent} % ({done}/{total} {unit}), {time}\n")
}

/// `21 s`, `12 min 34 s`, `2 h 03 min`.
fn wall_time(elapsed: Duration) -> String {
    let s = elapsed.as_secs();
    match s {
        0..120 => format!("{s} s"),
        120..7200 => format!("{} min {:02} s", s / 60, s % 60),
        _ => format!("{} h {:02} min", s / 3600, s / 60 % 60),
    }
}

/// The ticks of one thread's hot loop (a minimisation's evaluations), passed on to its
/// [`Progress`] every [`STRIDE`] calls and when dropped: a call costs an increment and a
/// comparison, never the shared count or the clock. Usable inside `Fn` closures.
pub struct Counter<'a> {
    progress: &'a Progress,
    pending: Cell<u64>,
    calls: Cell<u32>,
}

impl fmt::Debug for Counter<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Counter")
            .field("pending", &self.pending.get())
            .field("calls", &self.calls.get())
            .finish()
    }
}

impl Counter<'_> {
    /// One unit done.
    pub fn tick(&self) {
        self.add(1);
    }

    /// Work that completes no unit (an evaluation inside a long restart): a line may
    /// fall due meanwhile.
    pub fn beat(&self) {
        self.add(0);
    }

    /// `n` units done, as one call.
    pub fn add(&self, n: u64) {
        if self.progress.shown.is_none() {
            return;
        }
        self.pending.set(self.pending.get() + n);
        let calls = self.calls.get() + 1;
        if calls < STRIDE {
            self.calls.set(calls);
            return;
        }
        self.calls.set(0);
        self.progress.add(self.pending.replace(0));
    }
}

impl Drop for Counter<'_> {
    fn drop(&mut self) {
        let n = self.pending.replace(0);
        if n > 0 {
            self.progress.add(n);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;
    use std::sync::Arc;

    /// A clock the test sets (counting how often it is read) and the text written.
    #[derive(Clone, Default)]
    struct Fake {
        millis: Arc<AtomicU64>,
        reads: Arc<AtomicU64>,
        text: Arc<Mutex<Vec<u8>>>,
    }

    impl Write for Fake {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.text.lock().unwrap().extend_from_slice(buf);
            Ok(buf.len())
        }

        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    impl Fake {
        /// A design of `total` evaluations reported to this fake.
        fn progress(&self, total: u64) -> Progress {
            let (millis, reads) = (self.millis.clone(), self.reads.clone());
            let clock = move || {
                reads.fetch_add(1, Ordering::Relaxed);
                Duration::from_millis(millis.load(Ordering::Relaxed))
            };
            Progress::to_lines("excite: design", total, "evaluations", clock, self.clone())
        }

        fn at_millis(&self, ms: u64) {
            self.millis.store(ms, Ordering::Relaxed);
        }

        fn lines(&self) -> Vec<String> {
            let text = String::from_utf8(self.text.lock().unwrap().clone()).unwrap();
            text.lines().map(str::to_owned).collect()
        }

        fn reads(&self) -> u64 {
            self.reads.load(Ordering::Relaxed)
        }
    }

    /// A step that ends within the first interval writes nothing, although the clock was
    /// read (the check ran and found no line due).
    #[test]
    fn a_quick_step_writes_nothing() {
        let fake = Fake::default();
        let progress = fake.progress(300);
        let counter = progress.counter();
        for k in 0..300 {
            fake.at_millis(k * 33); // the last at 9.867 s
            counter.tick();
        }
        drop(counter);
        progress.add(0);
        progress.finish();
        assert!(
            fake.reads() >= 4,
            "the clock was read {} times",
            fake.reads()
        );
        assert_eq!(fake.lines(), Vec::<String>::new());
    }

    /// The first line at 10 s, the next 10 s after it (not before, however often the
    /// step reports), each a plain line with the count, the share and the time.
    #[test]
    fn lines_come_at_the_interval_and_never_more_often() {
        let fake = Fake::default();
        let progress = fake.progress(300);
        for (ms, n) in [
            (0, 10),
            (9_999, 10),
            (10_000, 100), // due: 120 of 300
            (15_000, 30),
            (19_999, 0),
            (21_500, 0), // due: 10 s after the last line
            (30_000, 100),
            (31_499, 0),
            (31_500, 60), // due: 310 of 300, held at the total
            (40_000, 5),
        ] {
            fake.at_millis(ms);
            progress.add(n);
        }
        progress.finish();
        let lines = fake.lines();
        assert_eq!(
            lines,
            [
                "excite: design 40 % (120/300 evaluations), 10 s",
                "excite: design 50 % (150/300 evaluations), 21 s",
                "excite: design 100 % (300/300 evaluations), 31 s",
            ]
        );
        let text = fake.text.lock().unwrap();
        assert!(
            text.iter()
                .all(|&b| b == b'\n' || (b' '..=b'~').contains(&b)),
            "{text:?}"
        );
    }

    /// A hot loop through counters: the clock read once per [`STRIDE`] calls, lines at
    /// least [`INTERVAL`] apart and about one per interval, every tick counted.
    #[test]
    fn counters_read_the_clock_once_per_stride() {
        let fake = Fake::default();
        let ticks = 100_000;
        let progress = fake.progress(ticks);
        let counter = progress.counter();
        for k in 0..ticks {
            fake.at_millis(k); // 1 ms per tick: 100 s
            counter.tick();
        }
        drop(counter);
        let reads = fake.reads();
        assert!(
            reads == ticks / u64::from(STRIDE) + 1,
            "{reads} clock readings for {ticks} ticks"
        );
        let seconds: Vec<u64> = fake
            .lines()
            .iter()
            .map(|l| {
                let (_, time) = l.rsplit_once(", ").unwrap();
                time.strip_suffix(" s").unwrap().parse().unwrap()
            })
            .collect();
        assert_eq!(seconds.len(), 9, "{:?}", fake.lines());
        assert!(seconds[0] >= 10, "{seconds:?}");
        assert!(seconds.windows(2).all(|w| w[1] >= w[0] + 10), "{seconds:?}");
        // every tick arrived: the count of a line written now
        fake.at_millis(110_000);
        progress.add(0);
        assert_eq!(
            fake.lines().last().unwrap(),
            "excite: design 100 % (100000/100000 evaluations), 110 s"
        );
    }

    /// Ticks from many threads, each through its own counter, are all counted (the
    /// counters pass on what they hold when dropped).
    #[test]
    fn ticks_from_threads_are_all_counted() {
        let fake = Fake::default();
        let progress = fake.progress(1_000_000);
        (0..1000).into_par_iter().for_each(|_| {
            let counter = progress.counter();
            (0..1000).for_each(|_| counter.tick());
        });
        fake.at_millis(10_000);
        progress.add(0);
        assert_eq!(
            fake.lines(),
            ["excite: design 100 % (1000000/1000000 evaluations), 10 s"]
        );
    }

    /// Disabled, nothing is kept or shown; a step without a known total gives its count.
    #[test]
    fn disabled_shows_nothing_and_an_open_step_counts() {
        let progress = Progress::new(false, "excite: design", 10, "evaluations");
        progress.counter().tick();
        progress.tick();
        assert!(progress.shown.is_none());
        assert_eq!(
            line("identify", 7, 0, "blocks", Duration::from_secs(3)),
            "identify: 7 blocks, 3 s\n"
        );
    }

    /// Times up to two minutes in seconds, then minutes and seconds, then hours.
    #[test]
    fn wall_times_are_short() {
        let t = |s| wall_time(Duration::from_secs(s));
        assert_eq!(t(0), "0 s");
        assert_eq!(t(119), "119 s");
        assert_eq!(t(754), "12 min 34 s");
        assert_eq!(t(7384), "2 h 03 min");
    }
}
