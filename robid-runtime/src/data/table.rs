//! Reading selected columns of a CSV file (with header, optionally gzip-compressed).

use std::fs::File;
use std::io::{BufReader, Read};
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
    let mut file = File::open(path).map_err(io)?;
    let mut magic = [0u8; 2];
    let n = file.read(&mut magic).map_err(io)?;
    let file = File::open(path).map_err(io)?;
    if n == 2 && magic == [0x1f, 0x8b] {
        read_columns_from(
            BufReader::with_capacity(1 << 16, MultiGzDecoder::new(file)),
            path,
            names,
        )
    } else {
        read_columns_from(BufReader::with_capacity(1 << 16, file), path, names)
    }
}

/// Reads the columns `names` from any reader; `path` is used in messages.
pub fn read_columns_from(reader: impl Read, path: &Path, names: &[String]) -> Result<Table> {
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
        let mut enc =
            flate2::write::GzEncoder::new(File::create(&p).unwrap(), flate2::Compression::fast());
        enc.write_all(b"t,q\n0,1\n1,2\n").unwrap();
        enc.finish().unwrap();
        let t = read_columns(&p, &names(&["q"])).unwrap();
        assert_eq!(t.columns[0], vec![1.0, 2.0]);
        let e = read_columns(&dir.join("none.csv"), &names(&["q"])).unwrap_err();
        assert!(matches!(e, Error::Io { .. }));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
