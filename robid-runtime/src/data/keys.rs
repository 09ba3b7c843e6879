//! Where each key of a TOML file is, so that a value found wrong after parsing is reported
//! at its file:line:column (toml's spans).
//!
//! Keys are dotted paths; elements of arrays (of values or of tables) are numbered from 1:
//! `processing.lowpass.cutoff`, `source[2].torque`, `drive.gear_ratios[3]`,
//! `extra_column[4].terms[1].row`.

use std::collections::BTreeMap;

use toml::de::{DeTable, DeValue};

/// 1-based line and column of every key (or array element) of a TOML text.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct KeyMap {
    keys: BTreeMap<String, (usize, usize)>,
}

impl KeyMap {
    /// The keys of `text` (empty when it is not valid TOML: the parser reports that).
    pub fn parse(text: &str) -> KeyMap {
        let mut map = KeyMap::default();
        if let Ok(table) = DeTable::parse(text) {
            let starts = line_starts(text);
            map.walk(table.get_ref(), "", &starts, 0);
        }
        map
    }

    /// The line and column of `key`, or of its nearest enclosing key that is in the file
    /// (a table header, an array), or `None`.
    pub fn find(&self, key: &str) -> Option<(usize, usize)> {
        let mut k = key;
        loop {
            if let Some(&at) = self.keys.get(k) {
                return Some(at);
            }
            let cut = k.rfind(['.', '['])?;
            k = &k[..cut];
        }
    }

    /// The place of `key` when the file gives it, itself or a key under it
    /// (`processing.decimation`, `runs` for `[runs]` or `runs.files`); `None` otherwise.
    pub fn given(&self, key: &str) -> Option<(usize, usize)> {
        let under = |k: &str| {
            k.strip_prefix(key)
                .is_some_and(|rest| rest.is_empty() || rest.starts_with(['.', '[']))
        };
        self.keys
            .iter()
            .filter(|(k, _)| under(k))
            .map(|(_, at)| *at)
            .min()
    }

    /// Every key, in order.
    pub fn keys(&self) -> impl Iterator<Item = &str> {
        self.keys.keys().map(String::as_str)
    }

    /// The dotted path of the key written `name` that a value at byte `offset` of `text`
    /// (the text this map was parsed from) belongs to: the key or element at that place,
    /// else the last key named `name` before it (`processing.lowpass.order` for the `-1`
    /// of `lowpass = { cutoff = 5, order = -1 }` under `[processing]`).
    pub(crate) fn path_at(&self, text: &str, offset: usize, name: &str) -> Option<String> {
        let at = position(&line_starts(text), offset);
        if let Some((key, _)) = self.keys.iter().find(|(_, p)| **p == at) {
            return Some(key.clone());
        }
        let suffix = format!(".{name}");
        self.keys
            .iter()
            .filter(|(k, p)| **p <= at && (*k == name || k.ends_with(&suffix)))
            .max_by_key(|(_, p)| **p)
            .map(|(k, _)| k.clone())
    }

    fn walk(&mut self, table: &DeTable<'_>, prefix: &str, starts: &[usize], depth: usize) {
        // TOML nesting in a config is shallow; the cap keeps a hostile file from recursing
        if depth > 32 {
            return;
        }
        for (k, v) in table.iter() {
            let path = if prefix.is_empty() {
                k.get_ref().to_string()
            } else {
                format!("{prefix}.{}", k.get_ref())
            };
            self.keys
                .insert(path.clone(), position(starts, k.span().start));
            self.value(v.get_ref(), &path, starts, depth);
        }
    }

    fn value(&mut self, v: &DeValue<'_>, path: &str, starts: &[usize], depth: usize) {
        if depth > 32 {
            return;
        }
        match v {
            DeValue::Table(t) => self.walk(t, path, starts, depth + 1),
            DeValue::Array(a) => {
                for (i, e) in a.iter().enumerate() {
                    let p = format!("{path}[{}]", i + 1);
                    self.keys
                        .insert(p.clone(), position(starts, e.span().start));
                    self.value(e.get_ref(), &p, starts, depth + 1);
                }
            }
            _ => {}
        }
    }
}

fn line_starts(text: &str) -> Vec<usize> {
    std::iter::once(0)
        .chain(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i + 1),
        )
        .collect()
}

/// 1-based (line, column) of a byte offset (column in characters).
fn position(starts: &[usize], offset: usize) -> (usize, usize) {
    let line = starts.partition_point(|&s| s <= offset).max(1);
    (line, offset - starts[line - 1] + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_keys_array_elements_and_enclosing_tables() {
        let text = "dof = 2\n[[source]]\nposition = \"q{}\"\n[[source]]\ntorque = [\"a\", \"b\"]\n\
                    [processing]\nlowpass = { cutoff = 5.0 }\nrange = [0, 10]\n";
        let k = KeyMap::parse(text);
        assert_eq!(k.find("dof"), Some((1, 1)));
        assert_eq!(k.find("source[2].torque"), Some((5, 1)));
        assert_eq!(k.find("source[2].torque[2]"), Some((5, 16)));
        assert_eq!(k.find("processing.lowpass.cutoff"), Some((7, 13)));
        assert_eq!(k.find("processing.range[2]"), Some((8, 13)));
        // a key that is absent: its table
        assert_eq!(k.find("processing.trim"), Some((6, 2)));
        assert_eq!(k.find("sample_rate"), None);
        assert_eq!(KeyMap::parse("dof = [").find("dof"), None);
        // the path of a value's key: by its own place, or the last key of its name before
        let at = |needle: &str| text.find(needle).unwrap();
        assert_eq!(
            k.path_at(text, at("5.0"), "cutoff").as_deref(),
            Some("processing.lowpass.cutoff")
        );
        assert_eq!(
            k.path_at(text, at("\"b\""), "torque").as_deref(),
            Some("source[2].torque[2]")
        );
        assert_eq!(
            k.path_at(text, at("\"q{}\""), "position").as_deref(),
            Some("source[1].position")
        );
        assert_eq!(k.path_at(text, at("= 2"), "gaps"), None);
    }
}
