/// The fast path of `number` gives the standard library's value to the bit, on a log's
/// fields (3 to 8 decimals, signs, zeros) and on the edges of the fast path (15 and
/// 16 digits, 22 and 23 decimals, a lone point, exponents, words), which fall back.
/// A data file that is a pipe is refused before it is opened, by every reader of data
/// files: robid opens a data file more than once, and the second opening of a FIFO
/// waited forever for a writer (`identify --data fifo` hung; `--data /dev/stdin` fed
/// by `cat` was "empty"). Nothing writes to this FIFO: an opening would block.
#[test]
#[cfg(unix)]
fn a_pipe_is_refused_before_it_is_opened() {
    let dir = tempfile::tempdir().unwrap();
    let Some(fifo) = crate::output::fifo(dir.path(), "data.csv") else {
        return; // no mkfifo on this system
    };
    let said = |e: Error| {
        let e = e.to_string();
        assert!(
            e.contains("data.csv: a pipe, not a file") && e.contains("save the data to a file"),
            "{e}"
        );
    };
    said(read_header(&fifo).unwrap_err());
    said(open(&fifo).unwrap_err());
    let all = Optional { from: 0, rows: 0 };
    said(for_each_window_of(&fifo, &[], all, 1, |_, _| Ok(())).unwrap_err());
}

#[test]
fn plain_decimals_parse_as_the_standard_library() {
    let mut fields: Vec<String> = [
        "0",
        "-0",
        "+0",
        "0.0",
        "-0.0",
        "1.",
        ".5",
        "-.5",
        "+.5",
        ".",
        "-",
        "+",
        "",
        "1e3",
        "1.5E-3",
        "inf",
        "-inf",
        "NaN",
        "1..2",
        "1.2.3",
        " 1",
        "0x10",
        "1_0",
        "999999999999999",
        "9999999999999999",
        "123456789012345.6",
        "0.000000000000000000001",
        "0.0000000000000000000001",
        "0.00000000000000000000001",
        "0.1",
        "0.2",
        "0.3",
        "-1.57079633",
        "12.34500",
        "00000000000012.5",
        "3600.000",
        "-0.00000001",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let mut rng = crate::rng::Rng::new(7);
    for _ in 0..200_000 {
        let scale = 10f64.powi(rng.below(12) as i32 - 4);
        let v = (rng.unit() - 0.5) * scale;
        let decimals = rng.below(12);
        fields.push(format!("{v:.decimals$}"));
    }
    let mut fast = 0;
    for f in &fields {
        let expected = f.parse::<f64>().ok();
        let got = super::number(f.as_bytes());
        assert_eq!(
            got.map(f64::to_bits),
            expected.map(f64::to_bits),
            "{f:?}: {got:?} vs {expected:?}"
        );
        if let Some(v) = super::plain_decimal(f.as_bytes()) {
            assert_eq!(Some(v.to_bits()), expected.map(f64::to_bits), "{f:?}");
            fast += 1;
        }
    }
    // most of them take the fast path
    assert!(fast > 150_000, "{fast} of {}", fields.len());
}

use super::*;

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

fn read(text: &str, cols: &[&str]) -> Result<Table> {
    read_columns_from(text.as_bytes(), Path::new("mem.csv"), &names(cols))
}

#[test]
fn reads_selected_columns_in_order() {
    let t = read("# comment\na,b,c\n1,2,3\n4, 5 ,6e0\n", &["c", "a"]).unwrap();
    assert_eq!(t.columns, vec![vec![3.0, 6.0], vec![1.0, 4.0]]);
    assert_eq!(t.lines, vec![3, 4]);
}

/// The same text read in parallel blocks (no quotes) and in one block (a quote added in
/// a comment forces it) gives the same table, lines and errors.
#[test]
fn an_error_of_each_comes_before_a_later_windows_and_stops_the_reading() {
    // each window is handed on while the next is parsed: with the bad value in the
    // second window, the first window's error is the one reported, and `each` is not
    // called again
    let mut text = String::from("t,a\n");
    for k in 0..600 {
        text.push_str(&format!("{k},{k}\n"));
    }
    text.push_str("600,x\n");
    assert!(text.len() > 4096 && text.len() < 8192);
    let cols = names(&["a"]);
    let mut calls = 0;
    let e = for_each_window(text.as_bytes(), Path::new("m.csv"), &cols, 4096, |_, _| {
        calls += 1;
        Err(Error::setting("test", "each", "stop".to_string()))
    })
    .unwrap_err();
    assert!(e.to_string().contains("stop"), "{e}");
    assert_eq!(calls, 1);
    // without it, the text's error is reported after the first window was handed on
    let (mut calls, mut rows) = (0, 0);
    let e = for_each_window(text.as_bytes(), Path::new("m.csv"), &cols, 4096, |t, _| {
        calls += 1;
        rows += t.rows();
        Ok(())
    })
    .unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::NotANumber { line: 602, .. })),
        "{e}"
    );
    assert_eq!(calls, 1);
    assert!(rows > 400 && rows < 600, "{rows} rows in the first window");
}

/// A reader that gives `text`, then fails.
struct FailsAfter<'a>(&'a [u8]);

impl Read for FailsAfter<'_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.0.is_empty() {
            return Err(std::io::Error::other("the disk went away"));
        }
        let n = buf.len().min(self.0.len());
        buf[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        Ok(n)
    }
}

/// The next window's text is read while a window is parsed: an error of that reading
/// comes after the window's own error and after the window was handed on, as when the
/// text was read at the next window; the windows and the bytes read up to each end are
/// those of reading in turn.
#[test]
fn the_text_read_ahead_fails_where_reading_it_in_turn_would() {
    let mut text = String::from("t,a\n");
    for k in 0..2000 {
        text.push_str(&format!("{k},{k}\n"));
    }
    let cols = names(&["a"]);
    let mut handed = Vec::new();
    let e = for_each_window(
        FailsAfter(text.as_bytes()),
        Path::new("m.csv"),
        &cols,
        4096,
        |t, read| {
            handed.push((t.rows(), t.lines[0], read));
            Ok(())
        },
    )
    .unwrap_err();
    assert!(matches!(e, Error::Data(DataError::Io { .. })), "{e}");
    // the windows whose text was read before the failure were handed on, in order
    // (the rows after the last line end read are in none)
    let rows: usize = handed.iter().map(|h| h.0).sum();
    assert!(
        handed.len() >= 2 && rows > 1000 && rows < 2000,
        "{handed:?}"
    );
    for w in handed.windows(2) {
        assert_eq!(w[1].1, w[0].1 + w[0].0 as u64, "{handed:?}");
        assert!(w[1].2 > w[0].2, "{handed:?}");
    }
    // a bad value in the first window is reported before the failed read of the next
    let bad = text.replacen("7,7\n", "7,x\n", 1);
    let mut calls = 0;
    let e = for_each_window(
        FailsAfter(bad.as_bytes()),
        Path::new("m.csv"),
        &cols,
        4096,
        |_, _| {
            calls += 1;
            Ok(())
        },
    )
    .unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::NotANumber { line: 9, .. })),
        "{e}"
    );
    assert_eq!(calls, 0);
}

#[test]
fn blocks_and_one_block_agree_on_values_lines_and_errors() {
    let mut text = String::from("# made by a test\n t , a,b\r\n");
    for k in 0..200_000 {
        if k % 5000 == 0 {
            text.push_str("# comment\n\n");
        }
        text.push_str(&format!(
            "{},{:e}, {}\r\n",
            k,
            k as f64 * 0.37,
            -(k as f64) / 7.0
        ));
    }
    let quoted = format!("# \"quoted\"\n{text}");
    let cols = names(&["b", "t"]);
    let fast = read_columns_from(text.as_bytes(), Path::new("m.csv"), &cols).unwrap();
    let slow = read_columns_from(quoted.as_bytes(), Path::new("m.csv"), &cols).unwrap();
    assert!(fast.columns == slow.columns);
    // windows of a few lines (the header longer than the first ones), and a quote
    // that turns up in a later window, give the same rows and lines
    let late = text.replace("# comment\n\n150000,", "# \"comment\"\n\n150000,");
    assert_ne!(late, text);
    for (t, window) in [(&text, 7), (&text, 1000), (&text, 65_536), (&late, 999)] {
        let (mut table, mut calls) = (Vec::new(), 0);
        for_each_window(
            t.as_bytes(),
            Path::new("m.csv"),
            &cols,
            window,
            |part, _| {
                calls += 1;
                table.push(part);
                Ok(())
            },
        )
        .unwrap();
        // measured 115 windows of 65 536 bytes, 5 750 to 199 789 of the smaller ones
        assert!(calls > 58, "{calls} windows of {window} bytes");
        let columns: Vec<Vec<f64>> = (0..2)
            .map(|c| table.iter().flat_map(|p| p.columns[c].clone()).collect())
            .collect();
        let lines: Vec<u64> = table.iter().flat_map(|p| p.lines.clone()).collect();
        assert!(columns == fast.columns && lines == fast.lines, "{window}");
    }
    assert_eq!(fast.rows(), 200_000);
    // the true 1-based lines: 2 header lines, then 2 extra lines every 5000 records
    let line_of = |k: u64| 3 + k + 2 * (k / 5000 + 1);
    assert!((0..200_000u64).all(|k| fast.lines[k as usize] == line_of(k)));
    assert!((0..200_000usize).all(|k| slow.lines[k] == fast.lines[k] + 1));
    // an error far into the file (in a later parallel block) names its line and column
    for (t, shift) in [(&text, 0), (&quoted, 1)] {
        for window in [WINDOW, 4096] {
            let read = |t: &str, cols: &[String]| {
                let mut rows = 0;
                for_each_window(t.as_bytes(), Path::new("m.csv"), cols, window, |p, _| {
                    rows += p.rows();
                    Ok(())
                })
                .map(|()| rows)
            };
            let bad = format!("{t}200000,x,1\n");
            let e = read(&bad, &names(&["a"])).unwrap_err();
            assert!(
                matches!(&e, Error::Data(DataError::NotANumber { line, column, .. }) if *line == line_of(199_999) + 1 + shift && column == "a"),
                "{e}"
            );
            let ragged = format!("{t}200000,1\n");
            let e = read(&ragged, &cols).unwrap_err();
            assert!(
                matches!(e, Error::Data(DataError::Csv { line, .. }) if line == line_of(199_999) + 1 + shift),
                "{e}"
            );
        }
    }
}

/// A block's rows, lines, line ends and first error as text (NaN compared by bits).
fn described(part: &Part) -> String {
    let columns: Vec<Vec<u64>> = part
        .columns
        .iter()
        .map(|c| c.iter().map(|v| v.to_bits()).collect())
        .collect();
    let error = part
        .error
        .as_ref()
        .map(|e| match e {
            BlockError::Csv { line, reason } => format!("csv {line} {reason}"),
            BlockError::Value { line, want, text } => format!("value {line} {want} {text}"),
            BlockError::NotFinite {
                line, want, value, ..
            } => {
                format!("not finite {line} {want} {value}")
            }
            BlockError::Rows => "rows".into(),
        })
        .unwrap_or_default();
    format!("{columns:?} {:?} {} {error}", part.lines, part.newlines)
}

/// The plain lines' reader and the CSV reader give every block the same rows, lines,
/// line ends and errors: random blocks of numbers in every form a field may take
/// (fast-path decimals, exponents, spaces, 16 digits, words, empty, quoted, NaN),
/// `\n`, `\r\n` and lone `\r` line ends, blank and comment lines, rows of the wrong
/// length, the optional columns read or not, with each separator.
#[test]
fn plain_and_csv_readers_agree_on_every_block() {
    let tokens = [
        "1.5",
        "-0.25",
        "+3",
        "0",
        "-0",
        "12.",
        ".5",
        "1e3",
        "-2.5E-3",
        " 4.75 ",
        "\t6",
        "1234567890.12345",
        "1234567890.123456",
        "0.12345678901234567",
        "9007199254740993.3",
        "999999999999999.9",
        "-1.0000000000000001110223",
        "123456789012345678901",
        "0.0000000000000000000001",
        "abc",
        "",
        "nan",
        "inf",
        "-",
        ".",
        "\"7\"",
        "8\"",
        "1.2.3",
        "--1",
        "5 6",
    ];
    let mut rng = crate::rng::Rng::new(19);
    let (mut plain, mut total) = (0, 0);
    for case in 0..4000 {
        let separator = [",", ";", "\t"][case % 3];
        let fields = 1 + rng.below(4);
        let names: Vec<String> = (0..fields).map(|f| format!("c{f}")).collect();
        let header_text = format!("{}\n", names.join(separator));
        let wanted = [names[fields - 1].clone(), names[0].clone(), "none".into()];
        let required = 1 + rng.below(2);
        let header = Header::read(
            header_text.as_bytes(),
            true,
            Path::new("m.csv"),
            &wanted,
            required,
        )
        .unwrap()
        .unwrap();
        let mut text = String::new();
        for _ in 0..rng.below(6) {
            let odd = rng.below(10) == 0;
            match rng.below(40) {
                0 if odd => text.push('\n'),
                _ => {
                    if odd && rng.below(4) == 0 {
                        // a comment, whose fields may be numbers
                        text.push('#');
                    }
                    // mostly plain numbers, the other tokens now and then
                    let count = if odd { rng.below(6) } else { fields };
                    let row: Vec<String> = (0..count)
                        .map(|_| match rng.below(3) {
                            0 => tokens[rng.below(tokens.len())].to_string(),
                            _ => format!("{:.4}", rng.uniform(-9.0, 9.0)),
                        })
                        .collect();
                    text.push_str(&row.join(separator));
                    text.push_str(["\n", "\r\n", "\n", "\r"][rng.below(4)]);
                }
            }
        }
        if rng.below(3) == 0 {
            // the file's last line without its end
            text.pop();
        }
        for optional in [false, true] {
            let rows = AtomicUsize::new(0);
            let fast = block(text.as_bytes(), 0, text.len(), &header, optional, &rows);
            let slow = csv_block(text.as_bytes(), &header, optional, &AtomicUsize::new(0));
            assert_eq!(described(&fast), described(&slow), "{text:?} {optional}");
            if fast.error.is_none() {
                assert_eq!(rows.load(Ordering::Relaxed), fast.lines.len());
            }
            let read = if optional {
                header.want.len()
            } else {
                required
            };
            plain += usize::from(
                plain_rows(
                    text.as_bytes(),
                    header.separator,
                    header.fields,
                    &header.want,
                    required,
                    read,
                )
                .is_some(),
            );
            total += 1;
        }
    }
    // both readers are tried on many blocks
    assert!(
        plain > total / 4 && plain < total * 3 / 4,
        "{plain} of {total}"
    );
}

/// Each window's `read` is the bytes of text up to its end: whole lines, the rows in
/// them all handed on so far.
#[test]
fn each_window_is_handed_the_bytes_read_up_to_its_end() {
    let mut text = String::from("# a comment longer than the smallest window\nt,a\n");
    for k in 0..300 {
        text.push_str(&format!("{k},{}\n", k * 7));
    }
    for window in [5, 64, 1000] {
        let (mut rows, mut ends) = (0, Vec::new());
        for_each_window(
            text.as_bytes(),
            Path::new("m.csv"),
            &names(&["a"]),
            window,
            |t, read| {
                rows += t.rows();
                ends.push((read, rows));
                Ok(())
            },
        )
        .unwrap();
        assert!(ends.len() > 1, "{window}");
        for &(read, rows) in &ends {
            let upto = &text[..read];
            assert!(upto.ends_with('\n'), "{window}: {read}");
            // the comment and header lines hold no rows
            assert_eq!(upto.lines().count() - 2, rows, "{window}: {read}");
        }
        assert_eq!(ends.last(), Some(&(text.len(), 300)));
    }
}

/// A quoted field that holds line ends and is longer than the window, first seen in a
/// later window, is read whole: from there on the rest of the text is one block.
#[test]
fn a_late_quoted_field_longer_than_the_window_is_read_whole() {
    let mut text = String::from("t,a,note\n");
    for k in 0..800 {
        let note = if k == 400 {
            format!("\"{}\"", "a line, then\n".repeat(300))
        } else {
            String::new()
        };
        text.push_str(&format!("{k},{},{note}\n", k * 3));
    }
    let cols = names(&["t", "a"]);
    let whole = read_columns_from(text.as_bytes(), Path::new("m.csv"), &cols).unwrap();
    let a: Vec<f64> = (0..800).map(|k| f64::from(k * 3)).collect();
    assert_eq!(whole.columns[1], a);
    for window in [999, 2048] {
        let mut table = Vec::new();
        for_each_window(
            text.as_bytes(),
            Path::new("m.csv"),
            &cols,
            window,
            |t, _| {
                table.push(t);
                Ok(())
            },
        )
        .unwrap();
        assert!(table.len() >= 2, "{window}");
        let a: Vec<f64> = table.iter().flat_map(|t| t.columns[1].clone()).collect();
        let lines: Vec<u64> = table.iter().flat_map(|t| t.lines.clone()).collect();
        assert!(a == whole.columns[1] && lines == whole.lines, "{window}");
    }
}

/// A config that maps one column to two roles reads it twice, with or without quotes
/// (the two readers of the past disagreed here).
#[test]
fn one_column_read_twice_quoted_or_not() {
    for text in ["a,b\n1,2\n3,4\n", "\"a\",b\n1,\"2\"\n3,4\n"] {
        let t = read(text, &["a", "b", "a"]).unwrap();
        assert_eq!(
            t.columns,
            vec![vec![1.0, 3.0], vec![2.0, 4.0], vec![1.0, 3.0]]
        );
        assert_eq!(t.lines, vec![2, 3]);
    }
}

/// An optional column is NaN where it holds no finite number, and where it is
/// missing or named twice; the required columns' errors stay.
#[test]
fn optional_columns_are_nan_where_they_are_not_numbers() {
    let text = "a,t,b,b\n1,0.5,2,2\n3,x,4,4\n5,inf,6,6\n7,,8,8\n";
    let read = |cols: &[&str], from: usize| {
        let optional = Optional { from, rows: 10 };
        collect(
            text.as_bytes(),
            Path::new("m.csv"),
            &names(cols),
            optional,
            0,
        )
    };
    let t = read(&["a", "t", "none", "b"], 1).unwrap();
    assert_eq!(t.columns[0], [1.0, 3.0, 5.0, 7.0]);
    assert_eq!(t.columns[1][0], 0.5);
    assert!(t.columns[1][1..].iter().all(|v| v.is_nan()));
    assert!(t.columns[2..].iter().all(|c| c.len() == 4));
    assert!(t.columns[2..].iter().flatten().all(|v| v.is_nan()));
    assert!(matches!(
        read(&["t", "a"], 1).unwrap_err(),
        Error::Data(DataError::NotANumber { line: 3, .. })
    ));
    assert!(matches!(
        read(&["none", "a"], 1).unwrap_err(),
        Error::Data(DataError::MissingColumn { .. })
    ));
}

/// An optional column is read in its first rows only, whatever the windows, and a
/// window past them does not parse it: a field that is not a number there is not
/// seen.
#[test]
fn optional_columns_are_read_in_their_first_rows() {
    let mut text = String::from("t,a\n");
    for k in 0..3000 {
        text.push_str(&format!("{k},{}\n", 2 * k));
    }
    let cols = names(&["a", "t"]);
    let optional = Optional {
        from: 1,
        rows: 1234,
    };
    for window in [64, 1000, 4096, WINDOW] {
        let (mut a, mut t, mut calls) = (Vec::<f64>::new(), Vec::<f64>::new(), 0);
        windows_of(
            text.as_bytes(),
            Path::new("m.csv"),
            &cols,
            optional,
            window,
            |p, _| {
                calls += 1;
                assert!(p.columns[1].len() <= p.rows());
                a.extend(&p.columns[0]);
                t.extend(&p.columns[1]);
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(a.len(), 3000, "{window}");
        assert!(t.iter().copied().eq((0..1234).map(f64::from)), "{window}");
        assert!(window == WINDOW || calls > 5, "{window}: {calls} windows");
    }
}

#[test]
fn bom_crlf_and_quotes_are_accepted() {
    let plain = read("a,b\n1,2\n", &["a", "b"]).unwrap();
    for text in [
        "\u{feff}a,b\n1,2\n",
        "a,b\r\n1,2\r\n",
        "\u{feff}\"a\",\"b\"\r\n\"1\",2\r\n",
    ] {
        let t = read(text, &["a", "b"]).unwrap();
        assert_eq!(t.columns, plain.columns, "{text:?}");
        assert_eq!(t.lines, plain.lines, "{text:?}");
    }
}

/// A file of CR line ends (classic Mac OS) is refused with the conversion: it was read
/// as its header alone, told as a file without rows. A header alone, ending in CR, is
/// a header, and a CR inside a quoted field of a CR LF file is no line end.
#[test]
fn carriage_return_line_ends_are_named() {
    for text in ["a,b\r1,2\r3,4\r", "\u{feff}a,b\r1,2"] {
        let e = read(text, &["a", "b"]).unwrap_err();
        assert!(
            matches!(e, Error::Data(DataError::CarriageReturnLines { .. })),
            "{text:?}: {e}"
        );
        assert!(e.to_string().contains("tr '\\r' '\\n'"), "{e}");
    }
    assert_eq!(read("a,b\r", &["a", "b"]).unwrap().rows(), 0);
    let t = read("a,b\r\n\"1\r\",2\r\n", &["b"]).unwrap();
    assert_eq!(t.columns, [[2.0]]);
}

#[test]
fn duplicate_columns_name_both_positions() {
    let e = read("t,q1,q2,q2\n0,1,2,3\n", &["q2"]).unwrap_err();
    assert!(
        matches!(&e, Error::Data(DataError::DuplicateColumn { column, first: 3, second: 4, .. }) if column == "q2"),
        "{e}"
    );
    assert!(e.to_string().contains("fields 3 and 4"), "{e}");
    // a duplicated column that is not read is harmless
    assert!(read("t,x,x\n0,1,2\n", &["t"]).is_ok());
}

/// The separator the header uses is the file's: `;`, a tab or single spaces (UR's RTDE
/// recorder: `timestamp actual_q_0 ...`, `\r\n` line ends) read as commas are, after
/// comment and blank lines; `,` first where a header has several.
#[test]
fn the_header_line_sets_the_separator() {
    let commas = read(
        "# log\n\nt,q1,q 2\n0,1.5,-2\n0.001,1.25,-2e-3\n",
        &["q1", "t", "q 2"],
    )
    .unwrap();
    for text in [
        "# log\n\nt;q1;q 2\n0;1.5;-2\n0.001;1.25;-2e-3\n",
        "# log\n\nt\tq1\tq 2\n0\t1.5\t-2\n0.001\t1.25\t-2e-3\n",
        "# log, with a comma\r\n\r\nt q1 \"q 2\"\r\n0 1.5 -2\r\n0.001 1.25 -2e-3\r\n",
    ] {
        let t = read(text, &["q1", "t", "q 2"]).unwrap();
        assert_eq!(t.columns, commas.columns, "{text:?}");
        assert_eq!(t.lines, commas.lines, "{text:?}");
    }
    assert_eq!(
        read("a,b;c\n1,2\n", &["b;c"]).unwrap().columns,
        [[2.0]].map(Vec::from)
    );
    // a header line longer than the first window is read whole before its separator
    // is chosen (its first 16 bytes hold none)
    let text = "timestamp_in_seconds;q1\n0;1\n0.001;2\n";
    let mut got = Vec::new();
    let names = ["q1".to_owned()];
    for_each_window(text.as_bytes(), Path::new("t.csv"), &names, 16, |t, _| {
        got.extend(t.columns[0].clone());
        Ok(())
    })
    .unwrap();
    assert_eq!(got, [1.0, 2.0]);
    // a decimal comma (a spreadsheet's `;`-separated export) is told as such
    let e = read("t;q1\n0;1,5\n", &["q1"]).unwrap_err().to_string();
    assert!(
        e.contains("mem.csv:2") && e.contains("decimal point is `.`"),
        "{e}"
    );
    let e = read("t;q1\n0;abc\n", &["q1"]).unwrap_err().to_string();
    assert!(!e.contains("decimal point"), "{e}");
}

/// Columns aligned by runs of spaces (a text export, `printf` widths), with spaces
/// before the first field and lines of spaces alone, read as single spaces are; a row
/// short of a field is still told by its line.
#[test]
fn runs_of_spaces_separate_aligned_columns() {
    let single = read(
        "t q1 \"q 2\"\n0 1.5 -2\n0.001 1.25 -2e-3\n",
        &["q1", "t", "q 2"],
    )
    .unwrap();
    for text in [
        "    t      q1   \"q 2\"\n    0     1.5      -2\n0.001    1.25  -2e-3  \n",
        "t  q1  \"q 2\"\r\n0  1.5  -2\r\n   \r\n0.001  1.25  -2e-3\r\n",
    ] {
        let t = read(text, &["q1", "t", "q 2"]).unwrap();
        assert_eq!(t.columns, single.columns, "{text:?}");
    }
    let e = read("t   q1\n0   1\n0.001\n", &["q1"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("mem.csv:3") && e.contains("a row with 1 field,"),
        "{e}"
    );
}

/// Text without line ends (a device such as /dev/zero, a binary file) is refused once a
/// line has run [`MAX_LINE_BYTES`] without ending, in the header or after it (it was
/// read to the 4 GiB file limit: 8 GB of memory). The inputs stop at 48 MiB, so
/// that a reader without the limit ends too, with another error.
#[test]
fn a_line_without_end_is_refused_at_the_line_limit() {
    let endless = |head: &'static [u8]| head.chain(std::io::repeat(0).take(48 << 20));
    let names = ["q1".to_owned()];
    for (head, line) in [(&b""[..], 1), (b"# a log\nt,q1\n0,1\n", 4)] {
        let e = for_each_window(endless(head), Path::new("zero"), &names, WINDOW, |_, _| {
            Ok(())
        })
        .unwrap_err();
        assert!(
            matches!(&e, Error::Data(DataError::LineTooLong { line: l, limit, .. }) if *l == line && *limit >= MAX_LINE_BYTES && *limit < 2 * MAX_LINE_BYTES),
            "{e}"
        );
        assert!(e.to_string().contains("is this a CSV file"), "{e}");
    }
}

#[test]
fn other_separators_say_what_is_supported() {
    for (text, name, sep) in [
        ("t|q1\n0|1\n", "q1", "`|`"),
        ("t,q1\tq2\n0,1\t2\n", "q2", "tabs"),
    ] {
        let e = read(text, &[name]).unwrap_err();
        assert!(
            matches!(&e, Error::Data(DataError::UnsupportedSeparator { separator, .. }) if separator == sep),
            "{e}"
        );
        assert!(e.to_string().contains("convert the file to commas"), "{e}");
    }
}

#[test]
fn missing_column_lists_the_header() {
    let e = read("a,b\n1,2\n", &["q1"]).unwrap_err();
    assert!(matches!(e, Error::Data(DataError::MissingColumn { .. })));
    assert!(e.to_string().contains("found: a, b"), "{e}");
    // a header of many columns, or of long names, is listed in part
    let header: Vec<String> = (0..100).map(|i| format!("c{i}")).collect();
    let long = "x".repeat(50);
    let text = format!("{},{long}\n", header.join(","));
    let e = read(&text, &["q1"]).unwrap_err().to_string();
    assert!(
        e.contains("found: c0, c1,") && e.contains("c29, and 71 more)") && !e.contains("c30"),
        "{e}"
    );
    let e = read(&format!("{long},a\n1,2\n"), &["q1"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("found: {}.. (50 characters), a)", &long[..32])),
        "{e}"
    );
}

/// A header name with a character that prints as nothing is quoted with it escaped: a
/// zero-width space after `q1` was listed as `q1` beside "no column `q1`"; so are a
/// non-breaking space and a byte-order mark inside a name (one at the start of the file is
/// the file's and removed).
#[test]
fn missing_column_shows_invisible_characters_in_the_header() {
    let e = read("t,q1\u{200b},q\u{a0}2,x\u{feff}y\n1,2,3,4\n", &["q1"])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("found: t, q1\\u{200b}, q\\u{a0}2, x\\u{feff}y)"),
        "{e}"
    );
    // the name asked for, too
    let e = read("t,q1\n1,2\n", &["q1\u{200d}"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("no column `q1\\u{200d}`"), "{e}");
}

/// A binary file's first line is not echoed (its bytes reached the terminal, escape
/// sequences included): the error says the file is not text.
#[test]
fn a_header_that_is_not_text_is_not_echoed() {
    for text in ["\x1b[2J\x07garbage,x\n1,2\n", "a\u{0},b\n1,2\n"] {
        let e = read(text, &["q1"]).unwrap_err();
        assert!(
            matches!(e, Error::Data(DataError::NotText { line: 1, .. })),
            "{e}"
        );
        assert!(
            !e.to_string().contains('\x1b') && e.to_string().contains("not text"),
            "{e}"
        );
    }
    let bytes = b"\xff\xfe q,\x80\n1,2\n";
    let e = read_columns_from(&bytes[..], Path::new("b.csv"), &["q1".to_string()]).unwrap_err();
    assert!(matches!(e, Error::Data(DataError::NotText { .. })), "{e}");
}

#[test]
fn nan_and_inf_name_line_and_column() {
    let e = read("a,b\n1,2\n3,NaN\n", &["a", "b"]).unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::NotFinite { line: 3, .. })),
        "{e}"
    );
    assert!(e.to_string().contains("mem.csv:3: column `b`"), "{e}");
    let e = read("a\ninf\n", &["a"]).unwrap_err();
    assert!(matches!(
        e,
        Error::Data(DataError::NotFinite { line: 2, .. })
    ));
    assert!(e.to_string().contains("column `a` is inf;"), "{e}");
    // a number too large for a double is quoted as written, not called `inf`
    for (field, shown) in [("1e400", "`1e400`"), ("-2E+999", "`-2E+999`")] {
        let e = read(&format!("a\n{field}\n"), &["a"])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("column `a` is {shown}, beyond the largest number")),
            "{e}"
        );
    }
}

#[test]
fn out_of_range_values_name_line_and_column() {
    let t = read("t,qdd1\n0,1\n1,1e200\n", &["t", "qdd1"]).unwrap();
    let e = t
        .check_range(1, "qdd1", Quantity::Acceleration)
        .unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(e, Error::Data(DataError::OutOfRange { .. })),
        "{text}"
    );
    assert!(
        text.starts_with("mem.csv:3: column `qdd1`") && text.contains("1e8"),
        "{text}"
    );
    assert!(t.check_range(0, "t", Quantity::Time).is_ok());
    // the value as typed, not `2.5e3` (`{:e}`); the limit, a constant, as a power of ten
    let t = read("T1\n20\n2500\n", &["T1"]).unwrap();
    let e = t.check_range(0, "T1", Quantity::Temperature).unwrap_err();
    assert!(
        e.to_string().starts_with(
            "mem.csv:3: column `T1` is 2500, outside the accepted range -273.15 <= temperature <= 1e3;"
        ),
        "{e}"
    );
    // below absolute zero; absolute zero itself is a temperature
    let t = read("T1\n-273.15\n-273.2\n", &["T1"]).unwrap();
    let e = t.check_range(0, "T1", Quantity::Temperature).unwrap_err();
    assert!(
        e.to_string().starts_with(
            "mem.csv:3: column `T1` is -273.2, outside the accepted range -273.15 <= temperature <= 1e3; \
             repair or remove this row (a value below absolute zero"
        ),
        "{e}"
    );
}

#[test]
fn text_ragged_and_empty_are_errors() {
    // a control character is shown escaped: a NUL inside a number was invisible, the
    // field quoted as a number that "is not a number"
    let e = read("a,b\n1,2.5\x00e-3\n", &["b"]).unwrap_err();
    assert!(
        e.to_string()
            .contains("column `b` holds `2.5\\u{0}e-3`, which is not a number"),
        "{e}"
    );
    let e = read("a,b\n1,x\n", &["b"]).unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::NotANumber { line: 2, .. })),
        "{e}"
    );
    let e = read("a,b\n1,2\n3\n", &["a"]).unwrap_err();
    assert!(
        matches!(e, Error::Data(DataError::Csv { line: 3, .. })),
        "{e}"
    );
    // an empty file is told so without a count of rows, which is the caller's
    for text in ["", "# only a comment\n", "\n\n"] {
        let e = read(text, &["a"]).unwrap_err();
        assert!(
            matches!(e, Error::Data(DataError::EmptyFile { .. })),
            "{text:?}: {e}"
        );
        assert!(!e.to_string().contains("at least"), "{e}");
    }
}

#[test]
fn gzip_files_truncated_gzip_and_missing_files() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("x.csv.gz");
    let mut enc = flate2::write::GzEncoder::new(
        std::fs::File::create(&p).unwrap(),
        flate2::Compression::fast(),
    );
    let mut text = String::from("t,q\n");
    for k in 0..2000 {
        text.push_str(&format!("{k},{}\n", k as f64 * 0.5));
    }
    enc.write_all(text.as_bytes()).unwrap();
    enc.finish().unwrap();
    let t = read_columns(&p, &names(&["q"])).unwrap();
    assert_eq!(t.columns[0][..2], [0.0, 0.5]);
    let bytes = std::fs::read(&p).unwrap();
    let cut = dir.path().join("cut.csv.gz");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let e = read_columns(&cut, &names(&["q"])).unwrap_err();
    assert!(matches!(e, Error::Data(DataError::Corrupt { .. })), "{e}");
    assert!(e.to_string().contains("truncated or corrupt"), "{e}");
    // the header reader (the default column mapping's) says the same, as does a file
    // of the gzip magic number alone; they were "cannot read: ..; check the path and
    // permissions"
    let magic = dir.path().join("magic.csv");
    std::fs::write(&magic, [0x1f, 0x8b]).unwrap();
    for file in [&cut, &magic] {
        let e = read_header(file).unwrap_err();
        assert!(matches!(e, Error::Data(DataError::Corrupt { .. })), "{e}");
        let e = read_columns(file, &names(&["q"])).unwrap_err();
        assert!(matches!(e, Error::Data(DataError::Corrupt { .. })), "{e}");
    }
    let e = read_columns(&dir.path().join("none.csv"), &names(&["q"])).unwrap_err();
    assert!(matches!(e, Error::Data(DataError::Io { .. })));
}
