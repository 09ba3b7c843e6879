//! Reading selected columns of a CSV file (with header, optionally gzip-compressed).

use std::io::Read;
use std::path::{Path, PathBuf};

use flate2::read::MultiGzDecoder;

use crate::error::{Error, Result};

/// Selected columns of one CSV file, with the file line of every row.
#[derive(Debug, Clone)]
pub struct Table {
    /// The file.
    pub path: PathBuf,
    /// Requested columns in the requested order, each with one value per row.
    pub columns: Vec<Vec<f64>>,
    /// 1-based file line of each row (for error messages).
    pub lines: Vec<u64>,
}

impl Table {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.lines.len()
    }
}

/// Reads the columns `names` from a CSV file. A file whose first bytes are the gzip
/// magic number is decompressed. Lines starting with `#` are comments.
pub fn read_columns(path: &Path, names: &[String]) -> Result<Table> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    let bytes = std::fs::read(path).map_err(io)?;
    if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut text = Vec::with_capacity(4 * bytes.len());
        MultiGzDecoder::new(bytes.as_slice())
            .read_to_end(&mut text)
            .map_err(io)?;
        read_columns_bytes(&text, path, names)
    } else {
        read_columns_bytes(&bytes, path, names)
    }
}

/// Reads the columns `names` from any reader; `path` is used in messages.
///
/// The text is read whole; a file without quote characters is split by a simple
/// parallel scanner (lines cut at `\n`, fields at `,`, only the wanted fields parsed),
/// any other file goes through the `csv` crate. Both give the same table and errors.
pub fn read_columns_from(mut reader: impl Read, path: &Path, names: &[String]) -> Result<Table> {
    let mut text = Vec::new();
    reader.read_to_end(&mut text).map_err(|source| Error::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_columns_bytes(&text, path, names)
}

/// [`read_columns_from`] on text in memory.
fn read_columns_bytes(text: &[u8], path: &Path, names: &[String]) -> Result<Table> {
    if text.contains(&b'"') {
        read_with_csv(text, path, names)
    } else {
        fast::read(text, path, names)
    }
}

/// The general reader (quoted fields and all): the `csv` crate.
fn read_with_csv(reader: impl Read, path: &Path, names: &[String]) -> Result<Table> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(reader);
    let csv_err = |e: csv::Error| match e.kind() {
        csv::ErrorKind::Io(_) => Error::Csv {
            path: path.to_path_buf(),
            line: 0,
            reason: e.to_string(),
        },
        _ => Error::Csv {
            path: path.to_path_buf(),
            line: e.position().map_or(0, |p| p.line()),
            reason: e.to_string(),
        },
    };
    let header: Vec<String> = rdr
        .headers()
        .map_err(csv_err)?
        .iter()
        .map(str::to_string)
        .collect();
    let index = names
        .iter()
        .map(|name| {
            header
                .iter()
                .position(|h| h == name)
                .ok_or_else(|| Error::MissingColumn {
                    path: path.to_path_buf(),
                    column: name.clone(),
                    available: header.clone(),
                })
        })
        .collect::<Result<Vec<usize>>>()?;
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
    let mut lines = Vec::new();
    let mut record = csv::ByteRecord::new();
    while rdr.read_byte_record(&mut record).map_err(csv_err)? {
        let line = record.position().map_or(0, |p| p.line());
        for ((col, &i), name) in columns.iter_mut().zip(&index).zip(names) {
            let bytes = record.get(i).unwrap_or_default();
            let value = std::str::from_utf8(bytes)
                .ok()
                .and_then(|s| s.parse::<f64>().ok());
            match value {
                Some(v) if v.is_finite() => col.push(v),
                Some(v) => {
                    return Err(Error::NotFinite {
                        path: path.to_path_buf(),
                        line,
                        column: name.clone(),
                        value: v,
                    });
                }
                None => {
                    return Err(Error::NotANumber {
                        path: path.to_path_buf(),
                        line,
                        column: name.clone(),
                        text: String::from_utf8_lossy(bytes).into_owned(),
                    });
                }
            }
        }
        lines.push(line);
    }
    Ok(Table {
        path: path.to_path_buf(),
        columns,
        lines,
    })
}

/// The scanner for unquoted CSV text.
mod fast {
    use std::path::Path;

    use rayon::prelude::*;

    use super::Table;
    use crate::error::{Error, Result};

    /// Bytes per parallel chunk of the body.
    const CHUNK: usize = 1 << 20;

    fn trim(mut b: &[u8]) -> &[u8] {
        while let [first, rest @ ..] = b
            && first.is_ascii_whitespace()
        {
            b = rest;
        }
        while let [rest @ .., last] = b
            && last.is_ascii_whitespace()
        {
            b = rest;
        }
        b
    }

    /// The next line of `text` from `at` (without `\n` and a trailing `\r`) and where the
    /// one after it starts.
    fn line_at(text: &[u8], at: usize) -> (&[u8], usize) {
        let end = text[at..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(text.len(), |i| at + i);
        let mut line = &text[at..end];
        if let [rest @ .., b'\r'] = line {
            line = rest;
        }
        (line, end + 1)
    }

    /// What a chunk of data lines gave: columns, line numbers relative to the chunk's
    /// first line, newlines in the chunk, and the first error (with a relative line).
    struct Part {
        columns: Vec<Vec<f64>>,
        lines: Vec<u64>,
        newlines: u64,
        error: Option<Error>,
    }

    pub(super) fn read(text: &[u8], path: &Path, names: &[String]) -> Result<Table> {
        // header: the first line that is neither empty nor a comment
        let mut at = 0;
        let mut line_no = 0u64;
        let header: Vec<String> = loop {
            if at >= text.len() {
                break Vec::new();
            }
            let (line, next) = line_at(text, at);
            line_no += 1;
            at = next;
            if line.is_empty() || line[0] == b'#' {
                continue;
            }
            break line
                .split(|&b| b == b',')
                .map(|f| String::from_utf8_lossy(trim(f)).into_owned())
                .collect();
        };
        let mut want: Vec<Option<usize>> = vec![None; header.len()];
        for (k, name) in names.iter().enumerate() {
            let i = header
                .iter()
                .position(|h| h == name)
                .ok_or_else(|| Error::MissingColumn {
                    path: path.to_path_buf(),
                    column: name.clone(),
                    available: header.clone(),
                })?;
            want[i] = Some(k);
        }
        // chunks of the body cut after a newline
        let body = &text[at.min(text.len())..];
        let mut cuts = vec![0];
        while let Some(&last) = cuts.last() {
            let target = last + CHUNK;
            if target >= body.len() {
                break;
            }
            match body[target..].iter().position(|&b| b == b'\n') {
                Some(i) if target + i + 1 < body.len() => cuts.push(target + i + 1),
                _ => break,
            }
        }
        cuts.push(body.len());
        let fields = header.len();
        let parts: Vec<Part> = cuts
            .par_windows(2)
            .map(|w| chunk(&body[w[0]..w[1]], fields, &want, names.len()))
            .collect();
        let rows: usize = parts.iter().map(|p| p.lines.len()).sum();
        let mut columns: Vec<Vec<f64>> =
            (0..names.len()).map(|_| Vec::with_capacity(rows)).collect();
        let mut lines = Vec::with_capacity(rows);
        let mut offset = line_no;
        for p in parts {
            if let Some(e) = p.error {
                return Err(locate(e, offset, path, names));
            }
            for (c, v) in columns.iter_mut().zip(p.columns) {
                c.extend(v);
            }
            lines.extend(p.lines.iter().map(|l| l + offset));
            offset += p.newlines;
        }
        Ok(Table {
            path: path.to_path_buf(),
            columns,
            lines,
        })
    }

    /// Adds the chunk's line offset and the path to an error of [`chunk`].
    fn locate(e: Error, offset: u64, path: &Path, names: &[String]) -> Error {
        match e {
            Error::Csv { line, reason, .. } => Error::Csv {
                path: path.to_path_buf(),
                line: line + offset,
                reason,
            },
            Error::NotFinite {
                line,
                column,
                value,
                ..
            } => Error::NotFinite {
                path: path.to_path_buf(),
                line: line + offset,
                column: names
                    .get(column.parse::<usize>().unwrap_or(0))
                    .cloned()
                    .unwrap_or(column),
                value,
            },
            Error::NotANumber {
                line, column, text, ..
            } => Error::NotANumber {
                path: path.to_path_buf(),
                line: line + offset,
                column: names
                    .get(column.parse::<usize>().unwrap_or(0))
                    .cloned()
                    .unwrap_or(column),
                text,
            },
            e => e,
        }
    }

    /// Parses the data lines of `text` (whole lines). Errors carry the line relative to
    /// the chunk (1 = its first line) and the wanted column's index as its name.
    fn chunk(text: &[u8], fields: usize, want: &[Option<usize>], wanted: usize) -> Part {
        let estimate = text.len() / (fields.max(1) * 8) + 1;
        let mut part = Part {
            columns: (0..wanted).map(|_| Vec::with_capacity(estimate)).collect(),
            lines: Vec::with_capacity(estimate),
            newlines: 0,
            error: None,
        };
        let mut at = 0;
        while at < text.len() {
            let (line, next) = line_at(text, at);
            part.newlines += 1;
            at = next;
            let rel = part.newlines;
            if line.is_empty() || line[0] == b'#' {
                continue;
            }
            let mut count = 0;
            let mut from = 0;
            for end in line
                .iter()
                .enumerate()
                .filter_map(|(i, &b)| (b == b',').then_some(i))
                .chain(std::iter::once(line.len()))
            {
                let field = &line[from..end];
                from = end + 1;
                let i = count;
                count += 1;
                let Some(&Some(k)) = want.get(i) else {
                    continue;
                };
                let bytes = trim(field);
                let value = std::str::from_utf8(bytes)
                    .ok()
                    .and_then(|s| s.parse::<f64>().ok());
                match value {
                    Some(v) if v.is_finite() => part.columns[k].push(v),
                    Some(v) => {
                        part.error = Some(Error::NotFinite {
                            path: Default::default(),
                            line: rel,
                            column: k.to_string(),
                            value: v,
                        });
                        return part;
                    }
                    None => {
                        part.error = Some(Error::NotANumber {
                            path: Default::default(),
                            line: rel,
                            column: k.to_string(),
                            text: String::from_utf8_lossy(bytes).into_owned(),
                        });
                        return part;
                    }
                }
            }
            if count != fields {
                part.error = Some(Error::Csv {
                    path: Default::default(),
                    line: rel,
                    reason: format!(
                        "found record with {count} fields, but the header has {fields} fields"
                    ),
                });
                return part;
            }
            part.lines.push(rel);
        }
        part
    }
}

#[cfg(test)]
mod tests {
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

    #[test]
    fn the_scanner_and_the_csv_crate_agree() {
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
        let cols = names(&["b", "t"]);
        let fast = read_columns_from(text.as_bytes(), Path::new("m.csv"), &cols).unwrap();
        let slow = read_with_csv(text.as_bytes(), Path::new("m.csv"), &cols).unwrap();
        assert!(fast.columns == slow.columns);
        assert_eq!(fast.rows(), 200_000);
        // the true 1-based lines: 2 header lines, then 2 extra lines every 5000 records
        let line_of = |k: u64| 3 + k + 2 * (k / 5000 + 1);
        assert!((0..200_000u64).all(|k| fast.lines[k as usize] == line_of(k)));
        // an error far into the file (in a later parallel chunk) names its line and column
        let bad = format!("{text}200000,x,1\n");
        let e = read_columns_from(bad.as_bytes(), Path::new("m.csv"), &names(&["a"])).unwrap_err();
        assert!(
            matches!(&e, Error::NotANumber { line, column, .. } if *line == line_of(199_999) + 1 && column == "a"),
            "{e}"
        );
        let ragged = format!("{text}200000,1\n");
        let e = read_columns_from(ragged.as_bytes(), Path::new("m.csv"), &cols).unwrap_err();
        assert!(
            matches!(e, Error::Csv { line, .. } if line == line_of(199_999) + 1),
            "{e}"
        );
    }

    #[test]
    fn quoted_fields_use_the_csv_crate() {
        let t = read("\"a\",b\n\"1\",2\n", &["a", "b"]).unwrap();
        assert_eq!(t.columns, vec![vec![1.0], vec![2.0]]);
    }

    #[test]
    fn missing_column_lists_the_header() {
        let e = read("a,b\n1,2\n", &["q1"]).unwrap_err();
        assert!(matches!(e, Error::MissingColumn { .. }));
        assert!(e.to_string().contains("found: a, b"), "{e}");
    }

    #[test]
    fn nan_and_inf_name_line_and_column() {
        let e = read("a,b\n1,2\n3,NaN\n", &["a", "b"]).unwrap_err();
        assert!(matches!(e, Error::NotFinite { line: 3, .. }), "{e}");
        assert!(e.to_string().contains("mem.csv:3: column `b`"), "{e}");
        let e = read("a\ninf\n", &["a"]).unwrap_err();
        assert!(matches!(e, Error::NotFinite { line: 2, .. }));
    }

    #[test]
    fn text_and_ragged_rows_are_errors() {
        let e = read("a,b\n1,x\n", &["b"]).unwrap_err();
        assert!(matches!(e, Error::NotANumber { line: 2, .. }), "{e}");
        let e = read("a,b\n1,2\n3\n", &["a"]).unwrap_err();
        assert!(matches!(e, Error::Csv { line: 3, .. }), "{e}");
    }

    #[test]
    fn gzip_files_and_missing_files() {
        use std::io::Write;
        let dir = std::env::temp_dir().join(format!("robid-table-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("x.csv.gz");
        let mut enc = flate2::write::GzEncoder::new(
            std::fs::File::create(&p).unwrap(),
            flate2::Compression::fast(),
        );
        enc.write_all(b"t,q\n0,1\n1,2\n").unwrap();
        enc.finish().unwrap();
        let t = read_columns(&p, &names(&["q"])).unwrap();
        assert_eq!(t.columns[0], vec![1.0, 2.0]);
        let e = read_columns(&dir.join("none.csv"), &names(&["q"])).unwrap_err();
        assert!(matches!(e, Error::Io { .. }));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
