//! Restart files: the scenario and the opaque state of the run loop and the
//! solver, so a run can resume where it stopped.
//!
//! File layout: the 8 bytes [`CHECKPOINT_MAGIC`], then the bincode 1.3
//! encoding (fixed-width little-endian integers) of a [`Checkpoint`], whose
//! first field, the format version, thus sits in bytes 8..12, then (from
//! format version 2) the CRC-32 (IEEE) of every byte before it, as 4
//! little-endian bytes. A file whose checksum does not match is refused:
//! a checkpoint is either exactly what was written or an error.

use std::path::Path;

use bincode::Options;
use serde::{Deserialize, Serialize};

use crate::atomic::write_atomic;
use crate::IoError;

/// The first 8 bytes of every checkpoint file.
pub const CHECKPOINT_MAGIC: [u8; 8] = *b"BRISCKPT";

/// The format version this build writes and reads. Version 1 had no
/// checksum.
pub const CHECKPOINT_FORMAT_VERSION: u32 = 2;

/// Bytes of the checksum trailer.
const CHECKSUM_LEN: usize = 4;

/// What [`read_checkpoint`] calls its files in errors.
const KIND: &str = "Brisance checkpoint";

/// Everything needed to resume a run.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// Layout version of this structure; [`CHECKPOINT_FORMAT_VERSION`].
    pub format_version: u32,
    /// The scenario, as RON text, exactly as the run used it.
    pub scenario_ron: String,
    /// The run loop's state (step count, time, output counters, ...),
    /// encoded by its owner.
    pub run_state: Vec<u8>,
    /// The solver's state, encoded by the solver.
    pub solver_state: Vec<u8>,
}

impl Checkpoint {
    /// A checkpoint of the current format version.
    pub fn new(scenario_ron: String, run_state: Vec<u8>, solver_state: Vec<u8>) -> Self {
        Self {
            format_version: CHECKPOINT_FORMAT_VERSION,
            scenario_ron,
            run_state,
            solver_state,
        }
    }
}

/// The file name of the checkpoint taken at `step`:
/// `checkpoint_{step:08}.bin`, so names sort by step.
pub fn checkpoint_file_name(step: u64) -> String {
    format!("checkpoint_{step:08}.bin")
}

/// Writes `checkpoint` to `path` (atomically) with its checksum. Fails
/// without writing if its format version is not
/// [`CHECKPOINT_FORMAT_VERSION`], since this build could not read it back.
pub fn write_checkpoint(path: &Path, checkpoint: &Checkpoint) -> Result<(), IoError> {
    if checkpoint.format_version != CHECKPOINT_FORMAT_VERSION {
        return Err(IoError::invalid_input(
            path,
            format!(
                "checkpoint format version {} is not the supported version {}",
                checkpoint.format_version, CHECKPOINT_FORMAT_VERSION
            ),
        ));
    }
    let payload =
        bincode::serialize(checkpoint).map_err(|e| IoError::encode(path, e.to_string()))?;
    let mut bytes = Vec::with_capacity(CHECKPOINT_MAGIC.len() + payload.len() + CHECKSUM_LEN);
    bytes.extend_from_slice(&CHECKPOINT_MAGIC);
    bytes.extend_from_slice(&payload);
    let crc = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&crc.to_le_bytes());
    write_atomic(path, &bytes)
}

/// Reads a checkpoint written by [`write_checkpoint`], rejecting files that
/// do not start with [`CHECKPOINT_MAGIC`], have another format version
/// (an older one is named as such), are truncated, or whose checksum does
/// not match their content (any byte changed).
pub fn read_checkpoint(path: &Path) -> Result<Checkpoint, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::read(path, e))?;
    let malformed = |message: String| IoError::malformed(path, KIND, message);
    let truncated = || malformed(format!("the file is truncated ({} bytes)", bytes.len()));

    let magic_len = CHECKPOINT_MAGIC.len();
    let head = &bytes[..bytes.len().min(magic_len)];
    if head != &CHECKPOINT_MAGIC[..head.len()] {
        return Err(malformed(
            "it does not start with the checkpoint magic bytes".into(),
        ));
    }
    let version_bytes: [u8; 4] = bytes
        .get(magic_len..magic_len + 4)
        .and_then(|b| b.try_into().ok())
        .ok_or_else(truncated)?;
    let version = u32::from_le_bytes(version_bytes);
    if version < CHECKPOINT_FORMAT_VERSION {
        return Err(malformed(format!(
            "it was written by an older version of Brisance (checkpoint format {version}; this build reads format {CHECKPOINT_FORMAT_VERSION}): rerun from the start"
        )));
    }
    if version > CHECKPOINT_FORMAT_VERSION {
        return Err(malformed(format!(
            "format version {version} is not supported (this build reads version {CHECKPOINT_FORMAT_VERSION}; a newer Brisance wrote it, or the file is damaged)"
        )));
    }
    if bytes.len() < magic_len + 4 + CHECKSUM_LEN {
        return Err(truncated());
    }
    let body = checked_body(&bytes).map_err(malformed)?;
    let payload = &body[magic_len..];
    bincode::DefaultOptions::new()
        .with_fixint_encoding()
        .with_limit(payload.len() as u64)
        .reject_trailing_bytes()
        .deserialize(payload)
        .map_err(|e| match *e {
            bincode::ErrorKind::SizeLimit => truncated(),
            bincode::ErrorKind::Io(ref io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
                truncated()
            }
            other => malformed(other.to_string()),
        })
}

/// `bytes` without their CRC-32 trailer, or why the trailer does not
/// match them; the caller has checked that the trailer is there.
fn checked_body(bytes: &[u8]) -> Result<&[u8], String> {
    let (body, trailer) = bytes.split_at(bytes.len() - CHECKSUM_LEN);
    let stored = u32::from_le_bytes(trailer.try_into().expect("4 bytes"));
    let computed = crc32fast::hash(body);
    if stored != computed {
        return Err(format!(
            "its checksum does not match its content (stored {stored:08x}, computed {computed:08x}): the file is truncated or damaged"
        ));
    }
    Ok(body)
}

/// The first 8 bytes of every checkpoint piece file (one patch's part of
/// a checkpoint written per patch).
pub const PIECE_MAGIC: [u8; 8] = *b"BRISPIEC";

/// What [`read_checkpoint_piece`] calls its files in errors.
const PIECE_KIND: &str = "Brisance checkpoint piece";

/// The folder beside `checkpoint_{step:08}.bin` that holds the pieces of
/// a checkpoint written per patch: `checkpoint_{step:08}`.
pub fn checkpoint_pieces_dir_name(step: u64) -> String {
    format!("checkpoint_{step:08}")
}

/// The file of patch `patch`'s piece in that folder: `patch_{patch:05}.bin`.
pub fn checkpoint_piece_file_name(patch: usize) -> String {
    format!("patch_{patch:05}.bin")
}

/// Writes one patch's part of a checkpoint to `path` (atomically): the 8
/// bytes [`PIECE_MAGIC`], the format version (4 bytes), the part's
/// length (8 bytes), the part, and the CRC-32 of everything before it, all
/// little-endian.
pub fn write_checkpoint_piece(path: &Path, piece: &[u8]) -> Result<(), IoError> {
    let mut bytes = Vec::with_capacity(PIECE_MAGIC.len() + 12 + piece.len() + CHECKSUM_LEN);
    bytes.extend_from_slice(&PIECE_MAGIC);
    bytes.extend_from_slice(&CHECKPOINT_FORMAT_VERSION.to_le_bytes());
    bytes.extend_from_slice(&(piece.len() as u64).to_le_bytes());
    bytes.extend_from_slice(piece);
    let crc = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&crc.to_le_bytes());
    write_atomic(path, &bytes)
}

/// Reads a piece written by [`write_checkpoint_piece`], refusing a file
/// that does not start with [`PIECE_MAGIC`], has another format version,
/// is truncated or longer than it says, or whose checksum does not match.
pub fn read_checkpoint_piece(path: &Path) -> Result<Vec<u8>, IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::read(path, e))?;
    let malformed = |message: String| IoError::malformed(path, PIECE_KIND, message);
    let head = PIECE_MAGIC.len() + 12;
    if bytes.len() < head + CHECKSUM_LEN {
        return Err(malformed(format!(
            "the file is truncated ({} bytes)",
            bytes.len()
        )));
    }
    if bytes[..PIECE_MAGIC.len()] != PIECE_MAGIC {
        return Err(malformed(
            "it does not start with the checkpoint piece magic bytes".into(),
        ));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if version != CHECKPOINT_FORMAT_VERSION {
        return Err(malformed(format!(
            "format version {version} is not the version {CHECKPOINT_FORMAT_VERSION} this build reads"
        )));
    }
    let len = u64::from_le_bytes(bytes[12..20].try_into().expect("8 bytes"));
    if len != (bytes.len() - head - CHECKSUM_LEN) as u64 {
        return Err(malformed(format!(
            "it says it holds {len} bytes but holds {}: the file is truncated or damaged",
            bytes.len() - head - CHECKSUM_LEN
        )));
    }
    let body = checked_body(&bytes).map_err(malformed)?;
    Ok(body[head..].to_vec())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_piece_round_trips_and_any_damage_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(checkpoint_pieces_dir_name(42), "checkpoint_00000042");
        assert_eq!(checkpoint_piece_file_name(7), "patch_00007.bin");
        let path = dir.path().join(checkpoint_piece_file_name(7));
        let piece: Vec<u8> = (0..=255).collect();
        write_checkpoint_piece(&path, &piece).unwrap();
        assert_eq!(read_checkpoint_piece(&path).unwrap(), piece);
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes.len(), 8 + 4 + 8 + 256 + 4);
        // Every truncation, and a flipped bit anywhere, is an error naming
        // the file.
        for len in 0..bytes.len() {
            std::fs::write(&path, &bytes[..len]).unwrap();
            let err = read_checkpoint_piece(&path).unwrap_err().to_string();
            assert!(err.contains(&path.display().to_string()), "{err}");
        }
        for at in [0, 9, 13, 100, bytes.len() - 1] {
            let mut bad = bytes.clone();
            bad[at] ^= 0x10;
            std::fs::write(&path, &bad).unwrap();
            assert!(read_checkpoint_piece(&path).is_err(), "byte {at}");
        }
        let err = read_checkpoint_piece(&dir.path().join("none.bin")).unwrap_err();
        assert!(err.to_string().contains("none.bin"), "{err}");
    }

    fn f64_bytes(values: &[f64]) -> Vec<u8> {
        values.iter().flat_map(|x| x.to_le_bytes()).collect()
    }

    fn sample() -> Checkpoint {
        Checkpoint::new(
            "(name: \"test\", end_time: 1e-3)".to_string(),
            f64_bytes(&[0.1 + 0.2, 1e-300]),
            f64_bytes(&[f64::NAN, -0.0, f64::INFINITY, 5e-324, 1.0 / 3.0]),
        )
    }

    fn write_sample(dir: &Path) -> std::path::PathBuf {
        let path = dir.join(checkpoint_file_name(42));
        write_checkpoint(&path, &sample()).unwrap();
        path
    }

    #[test]
    fn file_name_is_zero_padded_step() {
        assert_eq!(checkpoint_file_name(42), "checkpoint_00000042.bin");
        assert_eq!(
            checkpoint_file_name(123_456_789),
            "checkpoint_123456789.bin"
        );
    }

    #[test]
    fn round_trip_preserves_payload_bits() {
        let dir = tempfile::tempdir().unwrap();
        let path = write_sample(dir.path());
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"BRISCKPT");
        assert_eq!(&bytes[8..12], &2u32.to_le_bytes());
        let (body, crc) = bytes.split_at(bytes.len() - 4);
        assert_eq!(crc, crc32fast::hash(body).to_le_bytes());
        let back = read_checkpoint(&path).unwrap();
        assert_eq!(back, sample());
        let nan_bits = u64::from_le_bytes(back.solver_state[..8].try_into().unwrap());
        assert_eq!(nan_bits, f64::NAN.to_bits());
    }

    #[test]
    fn every_truncation_is_reported_as_truncated() {
        let dir = tempfile::tempdir().unwrap();
        let path = write_sample(dir.path());
        let bytes = std::fs::read(&path).unwrap();
        for len in 0..bytes.len() {
            std::fs::write(&path, &bytes[..len]).unwrap();
            let err = read_checkpoint(&path).unwrap_err();
            let text = err.to_string();
            assert!(
                text.starts_with(&format!(
                    "{} is not a valid Brisance checkpoint",
                    path.display()
                )),
                "{text}"
            );
            assert!(text.contains("truncated"), "length {len}: {text}");
        }
    }

    #[test]
    fn wrong_magic_is_rejected() {
        let dir = tempfile::tempdir().unwrap();
        let path = write_sample(dir.path());
        let mut bytes = std::fs::read(&path).unwrap();
        bytes[0] = b'X';
        std::fs::write(&path, &bytes).unwrap();
        let text = read_checkpoint(&path).unwrap_err().to_string();
        assert!(text.contains("magic bytes"), "{text}");
        std::fs::write(&path, b"hello").unwrap();
        let text = read_checkpoint(&path).unwrap_err().to_string();
        assert!(text.contains("magic bytes"), "{text}");
    }

    /// A file of format `version` as `write_checkpoint` lays it out
    /// (`with_crc`: with the checksum trailer).
    fn file_of_version(version: u32, with_crc: bool) -> Vec<u8> {
        let mut c = sample();
        c.format_version = version;
        let mut bytes = CHECKPOINT_MAGIC.to_vec();
        bytes.extend(bincode::serialize(&c).unwrap());
        if with_crc {
            let crc = crc32fast::hash(&bytes);
            bytes.extend(crc.to_le_bytes());
        }
        bytes
    }

    #[test]
    fn other_format_version_is_rejected() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("future.bin");
        std::fs::write(&path, file_of_version(3, true)).unwrap();
        let text = read_checkpoint(&path).unwrap_err().to_string();
        assert!(text.contains("format version 3 is not supported"), "{text}");

        let mut future = sample();
        future.format_version = 3;
        let err = write_checkpoint(&path, &future).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
    }

    #[test]
    fn a_checkpoint_of_the_older_format_without_checksum_is_named_as_older() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("checkpoint_00000001.bin");
        std::fs::write(&path, file_of_version(1, false)).unwrap();
        let text = read_checkpoint(&path).unwrap_err().to_string();
        assert!(text.starts_with(&path.display().to_string()), "{text}");
        assert!(
            text.contains("written by an older version of Brisance (checkpoint format 1"),
            "{text}"
        );
    }

    #[test]
    fn a_few_changed_bytes_anywhere_are_refused_naming_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = write_sample(dir.path());
        let good = std::fs::read(&path).unwrap();
        let n = good.len();
        // Start (after the magic and version, which have their own
        // messages), middle of the scenario text, the state payload, the
        // checksum itself, the very last byte; one bit and whole bytes.
        for (offset, xor) in [
            (12, 0x01),
            (13, 0xff),
            (20, 0x20),
            (n / 2, 0x01),
            (n / 2 + 1, 0x80),
            (n - 12, 0x10),
            (n - 5, 0x01),
            (n - 4, 0x01),
            (n - 1, 0x80),
        ] {
            let mut bytes = good.clone();
            bytes[offset] ^= xor;
            std::fs::write(&path, &bytes).unwrap();
            let text = read_checkpoint(&path)
                .expect_err(&format!("byte {offset} ^ {xor:#x} accepted"))
                .to_string();
            assert!(
                text.starts_with(&format!(
                    "{} is not a valid Brisance checkpoint",
                    path.display()
                )),
                "{text}"
            );
            assert!(text.contains("checksum"), "byte {offset}: {text}");
        }
        // Several bytes at once, spread over the file.
        let mut bytes = good.clone();
        for k in [9, n / 3, 2 * n / 3, n - 2] {
            bytes[k] = bytes[k].wrapping_add(7);
        }
        std::fs::write(&path, &bytes).unwrap();
        assert!(read_checkpoint(&path).is_err());
        std::fs::write(&path, &good).unwrap();
        assert_eq!(read_checkpoint(&path).unwrap(), sample());
    }

    #[test]
    fn trailing_bytes_are_rejected() {
        let dir = tempfile::tempdir().unwrap();
        let path = write_sample(dir.path());
        let mut bytes = std::fs::read(&path).unwrap();
        bytes.push(0);
        std::fs::write(&path, &bytes).unwrap();
        assert!(read_checkpoint(&path).is_err());
    }

    #[test]
    fn missing_file_is_a_read_error_naming_it() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("nope.bin");
        let err = read_checkpoint(&path).unwrap_err();
        assert!(matches!(err, IoError::Read { .. }), "{err:?}");
        assert_eq!(err.path(), path);
    }
}
