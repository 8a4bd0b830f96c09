//! The error type shared by every writer and reader in this crate.

use std::path::{Path, PathBuf};

/// Why reading or writing an output file failed. Every message names the
/// file or directory involved, e.g.
/// `cannot write /x/y.vti: Permission denied (os error 13)`.
#[derive(Debug, thiserror::Error)]
pub enum IoError {
    /// Writing (or replacing) a file failed at the operating-system level.
    #[error("cannot write {}: {error}", path.display())]
    Write {
        /// The file that was being written.
        path: PathBuf,
        /// The underlying operating-system error.
        error: std::io::Error,
    },
    /// Reading a file failed at the operating-system level.
    #[error("cannot read {}: {error}", path.display())]
    Read {
        /// The file that was being read.
        path: PathBuf,
        /// The underlying operating-system error.
        error: std::io::Error,
    },
    /// A directory could not be created.
    #[error("cannot create directory {}: {error}", path.display())]
    CreateDir {
        /// The directory that was being created.
        path: PathBuf,
        /// The underlying operating-system error.
        error: std::io::Error,
    },
    /// A directory exists (or was created) but no file can be created in it.
    #[error("output directory {} is not writable: {error}", path.display())]
    NotWritable {
        /// The directory that was probed.
        path: PathBuf,
        /// The underlying operating-system error.
        error: std::io::Error,
    },
    /// The data handed to a writer is inconsistent (mismatched lengths, a
    /// name that cannot be stored, ...), so nothing was written.
    #[error("cannot write {}: {message}", path.display())]
    InvalidInput {
        /// The file that would have been written.
        path: PathBuf,
        /// What is wrong with the data.
        message: String,
    },
    /// Serialising the data into the file format failed.
    #[error("cannot encode {}: {message}", path.display())]
    Encode {
        /// The file that would have been written.
        path: PathBuf,
        /// What the encoder reported.
        message: String,
    },
    /// A file was read but its contents are not what the reader expects
    /// (wrong magic, truncated, unsupported version, malformed row, ...).
    #[error("{} is not a valid {kind}: {message}", path.display())]
    Malformed {
        /// The file that was read.
        path: PathBuf,
        /// The kind of file that was expected, e.g. `Brisance checkpoint`.
        kind: &'static str,
        /// What is wrong with it.
        message: String,
    },
}

impl IoError {
    /// A [`IoError::Write`] for `path`.
    pub(crate) fn write(path: &Path, error: std::io::Error) -> Self {
        Self::Write {
            path: path.to_path_buf(),
            error,
        }
    }

    /// A [`IoError::Read`] for `path`.
    pub(crate) fn read(path: &Path, error: std::io::Error) -> Self {
        Self::Read {
            path: path.to_path_buf(),
            error,
        }
    }

    /// An [`IoError::InvalidInput`] for `path`.
    pub(crate) fn invalid_input(path: &Path, message: impl Into<String>) -> Self {
        Self::InvalidInput {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// An [`IoError::Encode`] for `path`.
    pub(crate) fn encode(path: &Path, message: impl Into<String>) -> Self {
        Self::Encode {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }

    /// An [`IoError::Malformed`] for `path`.
    pub(crate) fn malformed(path: &Path, kind: &'static str, message: impl Into<String>) -> Self {
        Self::Malformed {
            path: path.to_path_buf(),
            kind,
            message: message.into(),
        }
    }

    /// The file or directory the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Write { path, .. }
            | Self::Read { path, .. }
            | Self::CreateDir { path, .. }
            | Self::NotWritable { path, .. }
            | Self::InvalidInput { path, .. }
            | Self::Encode { path, .. }
            | Self::Malformed { path, .. } => path,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_path() {
        let p = Path::new("/x/y.vti");
        let denied = std::io::Error::from(std::io::ErrorKind::PermissionDenied);
        let e = IoError::write(p, denied);
        let text = e.to_string();
        assert!(text.starts_with("cannot write /x/y.vti: "), "{text}");
        assert!(text.to_lowercase().contains("permission denied"), "{text}");
        let e = IoError::malformed(p, "Brisance checkpoint", "wrong magic bytes");
        assert_eq!(
            e.to_string(),
            "/x/y.vti is not a valid Brisance checkpoint: wrong magic bytes"
        );
        assert_eq!(e.path(), p);
    }
}
