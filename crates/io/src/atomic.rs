//! Crash-safe file replacement and output-directory checks.
//!
//! [`write_atomic`] writes the new contents to a hidden temporary file next
//! to the target and renames it over the target only once the bytes are on
//! disk, so a run that is interrupted (killed, out of disk, power loss)
//! leaves either the old file or the complete new one, never half of one.

use std::fs::{self, File, OpenOptions};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::IoError;

/// Distinguishes temporary and probe files made by different threads of
/// the same process.
static UNIQUE: AtomicU64 = AtomicU64::new(0);

/// A name that no other writer in this or another process is using now.
fn unique_suffix() -> String {
    let n = UNIQUE.fetch_add(1, Ordering::Relaxed);
    format!("{}-{n}", std::process::id())
}

/// The directory a file path lives in (`.` for a bare file name).
fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Replaces the file at `path` with `bytes`, atomically.
///
/// The bytes go to `.<name>.tmp-<pid>-<n>` in the same directory, are
/// flushed and synced, and the temporary file is then renamed over `path`.
/// On any failure the temporary file is removed and `path` is untouched.
/// The directory must already exist (see [`ensure_dir`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    let name = path
        .file_name()
        .ok_or_else(|| IoError::invalid_input(path, "the path does not end in a file name"))?;
    let dir = parent_dir(path);
    let mut tmp_name = std::ffi::OsString::from(".");
    tmp_name.push(name);
    tmp_name.push(format!(".tmp-{}", unique_suffix()));
    let tmp = dir.join(tmp_name);

    let result = write_synced(&tmp, bytes).and_then(|()| fs::rename(&tmp, path));
    match result {
        Ok(()) => {
            sync_dir(dir);
            Ok(())
        }
        Err(error) => {
            // Best effort: the temporary file may not even exist.
            let _ = fs::remove_file(&tmp);
            Err(IoError::write(path, error))
        }
    }
}

/// Creates `tmp` (which must not exist), writes `bytes` and syncs it.
fn write_synced(tmp: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut file = OpenOptions::new().write(true).create_new(true).open(tmp)?;
    file.write_all(bytes)?;
    file.flush()?;
    file.sync_all()
}

/// Makes a completed rename durable where the platform allows it; a failure
/// here does not undo the (already visible) new file, so it is ignored.
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

/// Creates the directory `path` and any missing parents (no-op when it
/// already exists).
pub fn ensure_dir(path: &Path) -> Result<(), IoError> {
    fs::create_dir_all(path).map_err(|error| IoError::CreateDir {
        path: path.to_path_buf(),
        error,
    })
}

/// Creates the directory `path` if needed and checks that a file can be
/// created in it, by creating and removing a small probe file.
///
/// Call it before a run starts, so that an unwritable output directory is
/// reported before any time is spent computing.
pub fn check_writable_dir(path: &Path) -> Result<(), IoError> {
    ensure_dir(path)?;
    let probe: PathBuf = path.join(format!(".brisance-write-probe-{}", unique_suffix()));
    let not_writable = |error| IoError::NotWritable {
        path: path.to_path_buf(),
        error,
    };
    let created = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .and_then(|mut f| f.write_all(b"probe"));
    let removed = fs::remove_file(&probe);
    created.map_err(not_writable)?;
    removed.map_err(not_writable)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names_in(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn write_atomic_creates_and_replaces_without_leftovers() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("out.txt");
        write_atomic(&target, b"first version, longer").unwrap();
        write_atomic(&target, b"second").unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"second");
        assert_eq!(names_in(dir.path()), ["out.txt"]);
    }

    #[test]
    fn failed_write_removes_temp_file_and_names_target() {
        let dir = tempfile::tempdir().unwrap();
        // Renaming a file over a non-empty directory always fails.
        let target = dir.path().join("taken");
        fs::create_dir(&target).unwrap();
        fs::write(target.join("inside"), b"x").unwrap();
        let err = write_atomic(&target, b"data").unwrap_err();
        assert!(matches!(err, IoError::Write { .. }), "{err:?}");
        let text = err.to_string();
        assert!(text.starts_with(&format!("cannot write {}: ", target.display())));
        assert_eq!(names_in(dir.path()), ["taken"]);
    }

    #[test]
    fn write_atomic_into_missing_directory_fails_cleanly() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("missing").join("out.txt");
        let err = write_atomic(&target, b"data").unwrap_err();
        assert_eq!(err.path(), target);
        assert!(names_in(dir.path()).is_empty());
    }

    #[test]
    fn path_without_file_name_is_rejected() {
        let err = write_atomic(Path::new("/"), b"data").unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
    }

    #[test]
    fn check_writable_dir_creates_nested_dir_and_leaves_it_empty() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("a").join("b");
        check_writable_dir(&out).unwrap();
        assert!(out.is_dir());
        assert!(names_in(&out).is_empty());
    }

    #[test]
    fn check_writable_dir_fails_below_a_regular_file() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("plain");
        fs::write(&file, b"x").unwrap();
        let out = file.join("sub");
        let err = check_writable_dir(&out).unwrap_err();
        assert!(matches!(err, IoError::CreateDir { .. }), "{err:?}");
        assert!(err.to_string().contains(&out.display().to_string()));
    }

    #[cfg(unix)]
    #[test]
    fn check_writable_dir_fails_in_read_only_dir() {
        use std::os::unix::fs::PermissionsExt;
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("ro");
        fs::create_dir(&out).unwrap();
        fs::set_permissions(&out, fs::Permissions::from_mode(0o555)).unwrap();
        // Root ignores permission bits; only check when they are enforced.
        let enforced = File::create(out.join("x")).is_err();
        let result = check_writable_dir(&out);
        fs::set_permissions(&out, fs::Permissions::from_mode(0o755)).unwrap();
        if enforced {
            let err = result.unwrap_err();
            assert!(matches!(err, IoError::NotWritable { .. }), "{err:?}");
            assert!(err.to_string().contains("is not writable"));
        }
    }
}
