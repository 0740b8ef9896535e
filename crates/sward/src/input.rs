//! Input files (scenes, replay scripts, images), read so that no input can hang a run or
//! exhaust memory: only regular files are opened (a FIFO would block until something writes
//! to it, a device such as `/dev/zero` never ends), and a file larger than its kind can be
//! is refused before it is read. Errors name the file and say what is there.

use std::io::Read;
use std::path::Path;

use crate::error::{Error, Result};
use crate::output::not_regular;

/// The largest scene file or replay script read (text).
pub const MAX_TEXT_BYTES: u64 = 64 << 20;
/// The largest image file read (PNG height and density maps).
pub const MAX_IMAGE_BYTES: u64 = 512 << 20;

fn read_error(path: &Path, message: String) -> Error {
    Error::Read {
        path: path.to_path_buf(),
        source: std::io::Error::other(message),
    }
}

/// Reads the whole file at `path` when it is a regular file (links followed) of at most
/// `limit` bytes.
pub fn read_bytes(path: &Path, limit: u64) -> Result<Vec<u8>> {
    let io = |source: std::io::Error| Error::Read {
        path: path.to_path_buf(),
        source,
    };
    // Checked before opening: opening a FIFO for reading blocks until a writer appears.
    let meta = std::fs::metadata(path).map_err(io)?;
    if let Some(kind) = not_regular(&meta) {
        return Err(read_error(
            path,
            format!("it is {kind}, not a regular file; sward reads inputs only from files"),
        ));
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let len = file.metadata().map_err(io)?.len();
    if len > limit {
        return Err(read_error(
            path,
            format!("it is {len} bytes; allowed at most {limit} bytes for this kind of file"),
        ));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    // `take` guards against a file that grows while it is read.
    file.take(limit + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() as u64 > limit {
        return Err(read_error(
            path,
            format!("it grew past {limit} bytes while it was read"),
        ));
    }
    Ok(bytes)
}

/// Reads a text input (scene, replay script): a regular UTF-8 file of at most
/// [`MAX_TEXT_BYTES`].
pub fn read_text(path: &Path) -> Result<String> {
    let bytes = read_bytes(path, MAX_TEXT_BYTES)?;
    String::from_utf8(bytes).map_err(|e| {
        read_error(
            path,
            format!(
                "it is not UTF-8 text (invalid byte at offset {}); scene files and scripts \
                 are RON text",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_regular_files_of_bounded_size_are_read() {
        let dir = std::env::temp_dir().join(format!("sward-input-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let fifo = dir.join("fifo");
        assert!(std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success());
        // Returns at once (a blocking open would hang the test).
        let e = read_text(&fifo).unwrap_err().to_string();
        assert!(
            e.contains("FIFO") && e.contains("not a regular file"),
            "{e}"
        );
        let e = read_text(&dir).unwrap_err().to_string();
        assert!(e.contains("a directory"), "{e}");
        let big = dir.join("big");
        std::fs::write(&big, vec![b' '; 100]).unwrap();
        let e = read_bytes(&big, 99).unwrap_err().to_string();
        assert!(e.contains("100 bytes") && e.contains("at most 99"), "{e}");
        assert_eq!(read_bytes(&big, 100).unwrap().len(), 100);
        std::fs::write(&big, [0xff, 0xfe]).unwrap();
        let e = read_text(&big).unwrap_err().to_string();
        assert!(e.contains("not UTF-8"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
