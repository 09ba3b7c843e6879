//! The deepest and longest expressions the reader accepts are handled by every
//! walk (text form, evaluation, differentiation, simplification) on a small
//! stack: the nesting limit keeps the one recursive walk (the text form) and
//! the reader itself shallow. A 40 kB alpha nested 20,000 deep used to
//! overflow the stack of every command reading a description.

use robid_symbolic::expr::{MAX_EXPRESSION_LEN, MAX_NESTING};
use robid_symbolic::{Arena, Robot};

/// Runs `f` on a thread with a 128 KiB stack (a test thread has 2 MiB).
fn on_small_stack(f: impl FnOnce() + Send + 'static) {
    std::thread::Builder::new()
        .stack_size(128 * 1024)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap();
}

/// Expressions at the nesting limit: products of sums, calls, signs, powers.
fn deepest() -> Vec<String> {
    let n = MAX_NESTING;
    let mut alternating = String::from("x");
    for i in (0..n).rev() {
        alternating = format!("a{i}*(b{i} + {alternating})");
    }
    let mut powers = String::from("x");
    for _ in 0..n {
        powers = format!("({powers} - 1)^2");
    }
    vec![
        alternating,
        powers,
        format!("{}x{}", "sin(".repeat(n), ")".repeat(n)),
        format!("{}x", "-".repeat(n)),
        format!("{}x{}", "-(".repeat(n / 2), ")".repeat(n / 2)),
    ]
}

#[test]
fn deepest_accepted_expressions_fit_a_small_stack() {
    on_small_stack(|| {
        for text in deepest() {
            assert!(text.len() <= MAX_EXPRESSION_LEN, "{}", text.len());
            let mut a = Arena::new();
            let e = a.parse(&text).unwrap_or_else(|err| panic!("{err}: {text}"));
            let shown = a.display(e);
            let again = a
                .parse(&shown)
                .unwrap_or_else(|err| panic!("{err}: {shown}"));
            let x = a.symbol("x");
            let _ = a.diff(again, x);
            let _ = a.simplify(again);
            let names: Vec<String> = a
                .free_symbols(&[e])
                .into_iter()
                .map(|s| a.symbol_name(s).to_owned())
                .collect();
            let pairs: Vec<(&str, f64)> = names.iter().map(|n| (n.as_str(), 0.5)).collect();
            let values = a.values(&pairs);
            let v = a.eval(&[e], &values).unwrap()[0];
            assert!(v.is_finite(), "{text}: {v}");
        }
    });
}

/// The longest flat sums and products are read quickly and without recursion.
#[test]
fn longest_flat_expressions_are_read() {
    on_small_stack(|| {
        let n = MAX_EXPRESSION_LEN / 6;
        for op in ["+", "*", "-", "/"] {
            let text: Vec<String> = (0..n).map(|i| format!("x{i}")).collect();
            let text = text.join(op);
            assert!(text.len() <= MAX_EXPRESSION_LEN);
            let start = std::time::Instant::now();
            let mut a = Arena::new();
            let e = a.parse(&text).unwrap();
            let _ = a.display(e);
            assert!(
                start.elapsed().as_secs_f64() < 5.0,
                "{op}: {:?}",
                start.elapsed()
            );
        }
    });
}

/// A description whose values nest to the limit is read and derived.
#[test]
fn descriptions_at_the_limit_are_read_on_a_small_stack() {
    on_small_stack(|| {
        let n = MAX_NESTING;
        let deep = format!("{}0.5{}", "(".repeat(n), ")".repeat(n));
        let deeper = format!("({deep})");
        let text = |alpha: &str| {
            format!(
                "name = \"arm\"\nconvention = \"modified\"\n[[joints]]\nalpha = \"{alpha}\"\na = 0.3\n"
            )
        };
        assert!(Robot::from_toml(&text(&deep), "arm.toml").is_ok());
        let err = Robot::from_toml(&text(&deeper), "arm.toml").unwrap_err();
        assert!(err.to_string().contains("nest deeper than 64"), "{err}");
    });
}
