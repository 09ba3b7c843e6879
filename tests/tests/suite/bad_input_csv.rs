//! Class "one CSV behaviour" of issue 11: two readers once disagreed (a config that maps
//! one column to two roles failed with "expected 0 entries, found 1001" on a plain file and
//! succeeded on a file with a `"`). Now one reader gives quoted and unquoted files the same
//! result or the same error; a UTF-8 byte-order mark and CRLF line ends are accepted;
//! duplicate column names are an error naming both; another separator gets a message that
//! says what is supported; a truncated gzip file is called truncated or corrupt.

use robid_runtime::DataError;
use tests::fuzz_data;
use tests::scratch::Scratch;

use std::path::Path;

use robid_runtime::Error;
use robid_runtime::data::{Config, Dataset, load, read_columns};

/// Every field quoted.
fn quoted(text: &str) -> String {
    text.lines()
        .map(|l| {
            l.split(',')
                .map(|f| format!("\"{f}\""))
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn same(a: &Dataset, b: &Dataset) {
    assert_eq!(a.q, b.q);
    assert_eq!(a.qd, b.qd);
    assert_eq!(a.qdd, b.qdd);
    assert_eq!(a.tau, b.tau);
    assert_eq!(a.sample_time, b.sample_time);
    assert_eq!(
        a.origin.as_ref().map(|o| &o.lines),
        b.origin.as_ref().map(|o| &o.lines)
    );
}

fn config(text: &str) -> Config {
    Config::from_toml_str(text, Path::new("c.toml")).unwrap()
}

#[test]
fn quoted_and_unquoted_files_give_the_same_data_or_the_same_error() {
    let tmp = Scratch::new();
    let plain = fuzz_data::motion_csv(&fuzz_data::motion(200));
    let configs = [
        Config::default_mapping(),
        config(
            "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\n\
             acceleration = \"qdd{}\"\ntorque = \"tau{}\"\n",
        ),
        // one column in two roles (where the two readers once disagreed) is refused by both
        config(
            "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\n\
             acceleration = \"qd{}\"\ntorque = \"tau{}\"\n",
        ),
        config("sample_rate = 100.0\n[[source]]\nposition = \"q{}\"\ntorque = \"q{}\"\n"),
    ];
    for (k, c) in configs.iter().enumerate() {
        let a = load(c, &[tmp.write(&format!("plain{k}.csv"), &plain)], 6);
        let b = load(
            c,
            &[tmp.write(&format!("quoted{k}.csv"), &quoted(&plain))],
            6,
        );
        match (a, b) {
            (Ok(a), Ok(b)) => same(&a, &b),
            (Err(a), Err(b)) => {
                assert_eq!(a.to_string(), b.to_string());
                assert!(a.to_string().contains("reads column `q"), "{a}");
            }
            (a, b) => panic!("config {k}: {a:?} against {b:?}"),
        }
    }
    // the same errors, at the same line
    let broken = plain.replacen("\n0.05,", "\n0.05,x", 1);
    let ragged = {
        let mut l: Vec<&str> = plain.lines().collect();
        l[30] = "1,2,3";
        l.join("\n")
    };
    for (name, text) in [("broken", broken), ("ragged", ragged)] {
        let a = load(&configs[0], &[tmp.write(&format!("{name}.csv"), &text)], 6).unwrap_err();
        let b = load(
            &configs[0],
            &[tmp.write(&format!("{name}.csv"), &quoted(&text))],
            6,
        )
        .unwrap_err();
        assert_eq!(a.to_string(), b.to_string());
    }
}

#[test]
fn bom_and_crlf_are_accepted() {
    let tmp = Scratch::new();
    let plain = fuzz_data::motion_csv(&fuzz_data::motion(100));
    let reference = load(
        &Config::default_mapping(),
        &[tmp.write("ref.csv", &plain)],
        6,
    )
    .unwrap();
    for (name, text) in [
        ("bom.csv", format!("\u{feff}{plain}")),
        ("crlf.csv", plain.replace('\n', "\r\n")),
        (
            "both.csv",
            format!("\u{feff}{}", quoted(&plain).replace('\n', "\r\n")),
        ),
    ] {
        let d = load(&Config::default_mapping(), &[tmp.write(name, &text)], 6).unwrap();
        same(&reference, &d);
    }
}

#[test]
fn duplicate_column_names_are_an_error_naming_both() {
    let tmp = Scratch::new();
    let plain = fuzz_data::motion_csv(&fuzz_data::motion(50));
    let text = plain.replacen("q3,", "q2,", 1);
    let e = load(
        &Config::default_mapping(),
        &[tmp.write("dup.csv", &text)],
        6,
    )
    .unwrap_err();
    assert!(
        matches!(&e, Error::Data(DataError::DuplicateColumn { column, first: 3, second: 4, .. }) if column == "q2"),
        "{e}"
    );
    assert!(e.to_string().contains("`q2` twice (fields 3 and 4)"), "{e}");
}

/// A log separated by `;`, tabs, single spaces or runs of spaces (aligned columns) loads
/// as its comma version does (the header line's separator is the file's); `|` is refused
/// with what is read.
#[test]
fn other_separators_load_or_say_what_is_supported() {
    let tmp = Scratch::new();
    let plain = fuzz_data::motion_csv(&fuzz_data::motion(50));
    let config = Config::default_mapping();
    let commas = load(&config, &[tmp.write("commas.csv", &plain)], 6).unwrap();
    for (name, sep) in [
        ("semi.csv", ";"),
        ("tab.csv", "\t"),
        ("space.csv", " "),
        ("aligned.csv", "   "),
    ] {
        let data = load(&config, &[tmp.write(name, &plain.replace(',', sep))], 6).unwrap();
        assert_eq!(data.q, commas.q, "{name}");
        assert_eq!(data.tau, commas.tau, "{name}");
    }
    let e = load(
        &config,
        &[tmp.write("bar.csv", &plain.replace(',', "|"))],
        6,
    )
    .unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(&e, Error::Data(DataError::UnsupportedSeparator { separator, .. }) if separator == "`|`"),
        "{text}"
    );
    assert!(text.contains("convert the file to commas"), "{text}");
}

#[test]
fn a_truncated_gzip_is_called_truncated_or_corrupt() {
    let tmp = Scratch::new();
    let real =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/staubli_tx40/data/curr_data.csv.gz");
    let bytes = std::fs::read(real).unwrap();
    let cut = tmp.write("cut.csv.gz", "");
    std::fs::write(&cut, &bytes[..bytes.len() / 3]).unwrap();
    let e = read_columns(&cut, &["Joint_1".to_string()]).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(e, Error::Data(DataError::Corrupt { .. })),
        "{text}"
    );
    assert!(
        text.contains("truncated or corrupt") && !text.contains("permissions"),
        "{text}"
    );
}
