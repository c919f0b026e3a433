//! Output files that appear whole or not at all: everything is written to a temporary file
//! in the destination's directory and renamed over the destination on success, so a failed
//! run never leaves a partial file behind.

use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

/// A file being written: a temporary file beside `path`, renamed to `path` by
/// [`AtomicFile::commit`]; dropped without commit, it is deleted.
pub struct AtomicFile {
    path: PathBuf,
    writer: BufWriter<tempfile::NamedTempFile>,
}

impl AtomicFile {
    /// Starts writing `path` (its directory must exist or be creatable).
    pub fn create(path: &Path) -> Result<AtomicFile> {
        let directory = match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
            _ => PathBuf::from("."),
        };
        fs::create_dir_all(&directory)
            .with_context(|| format!("{}: cannot create the directory", directory.display()))?;
        let mut builder = tempfile::Builder::new();
        builder.prefix(".crowdgaze-").suffix(".tmp");
        // Like any new file (the umask applies), not the private 0600 of temporary files.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(fs::Permissions::from_mode(0o666));
        }
        let temporary = builder
            .tempfile_in(&directory)
            .with_context(|| format!("{}: cannot create a temporary file", directory.display()))?;
        Ok(AtomicFile {
            path: path.to_path_buf(),
            writer: BufWriter::new(temporary),
        })
    }

    /// The destination path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes and renames the temporary file to the destination.
    pub fn commit(self) -> Result<()> {
        let path = self.path;
        let temporary = self
            .writer
            .into_inner()
            .map_err(|e| e.into_error())
            .with_context(|| format!("{}: cannot write", path.display()))?;
        temporary
            .persist(&path)
            .map_err(|e| e.error)
            .with_context(|| format!("{}: cannot write", path.display()))?;
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.writer.write(buf)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.writer.flush()
    }
}

/// Writes `bytes` to `path` atomically.
pub fn write_file(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut file = AtomicFile::create(path)?;
    file.write_all(bytes)
        .with_context(|| format!("{}: cannot write", path.display()))?;
    file.commit()
}

/// A progress bar on standard error, hidden when standard error is not a terminal (or when
/// `quiet`).
pub fn progress(length: u64, message: &'static str, quiet: bool) -> ProgressBar {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(length).with_message(message);
    if let Ok(style) =
        ProgressStyle::with_template("{msg:>10} [{bar:40}] {pos}/{len} frames, {eta} left")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}
