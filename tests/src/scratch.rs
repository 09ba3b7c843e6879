//! A fresh folder for one test's files.
//!
//! Each test makes its own [`Scratch`], so tests running at once never share a file and a
//! file from an earlier run can never make a check pass; the folder is removed when the
//! value is dropped, also when the test panics.

use std::path::{Path, PathBuf};

/// A temporary folder owned by one test.
#[derive(Debug)]
pub struct Scratch(tempfile::TempDir);

impl Scratch {
    /// A new empty folder under the system's temporary directory.
    ///
    /// # Panics
    /// When the folder cannot be made (a test helper: the test fails).
    pub fn new() -> Self {
        Scratch(
            tempfile::Builder::new()
                .prefix("robid-test-")
                .tempdir()
                .unwrap(),
        )
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        self.0.path()
    }

    /// The path of `name` in the folder (the file is not made).
    pub fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }

    /// Writes `text` to `name` in the folder and returns its path.
    ///
    /// # Panics
    /// When the file cannot be written.
    pub fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.path(name);
        std::fs::write(&path, text).unwrap();
        path
    }
}

impl Default for Scratch {
    fn default() -> Self {
        Self::new()
    }
}
