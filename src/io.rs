//! Writing files safely, and CSV text: the lowest layer, used by the harness and the outputs
//! alike (nothing here knows about optics or cases).
//!
//! What a kill at any moment leaves behind:
//! - every file is written atomically ([`write_atomic`]: a temporary `.fringe-tmp-*` file in
//!   the same folder, synced, then renamed over the old one), so each file is complete-old or
//!   complete-new; a leftover temporary file is removed by the next run that writes there
//!   (`remove_stale_temp_files`);
//! - the golden files of one `--bless` are one set (`bless_set`): staged in
//!   `<golden>/.fringe-bless/`, made durable, committed by a `COMMIT` list, then renamed into
//!   place. A kill before the commit leaves the old set (the next run deletes the stage); a kill
//!   after it is rolled forward by the next run ([`recover_bless`]), so every run reads one
//!   whole set;
//! - writers of one folder (`--out`, the golden folder) hold an exclusive lock on the folder
//!   ([`lock_dir`]) while they write: two concurrent runs on one `--out` write one after the
//!   other, each leaving a whole set of reports.

use std::path::Path;

/// Prefix of the temporary files of [`write_atomic`].
pub(crate) const TEMP_PREFIX: &str = ".fringe-tmp-";

/// Folder (inside the golden folder) where a bless stages its set, and its commit mark.
pub(crate) const BLESS_STAGE: &str = ".fringe-bless";
const BLESS_COMMIT: &str = "COMMIT";

/// Write `bytes` to `path` atomically, creating the parent folder.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let mut tmp = tempfile::Builder::new()
        .prefix(TEMP_PREFIX)
        .tempfile_in(dir)?;
    std::io::Write::write_all(&mut tmp, bytes)?;
    tmp.as_file().sync_all()?;
    // Reports are for reading by anyone (tempfile creates 0600 files).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(0o644))?;
    }
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// Make `dir` (created if absent) and show that a file can be written in it, before any work
/// whose results would go there. Leaves at most the (empty) folder behind.
pub(crate) fn probe_writable(dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let mut tmp = tempfile::Builder::new()
        .prefix(TEMP_PREFIX)
        .tempfile_in(dir)?;
    std::io::Write::write_all(&mut tmp, b"fringe")?;
    tmp.as_file().sync_all()?;
    Ok(())
}

/// An exclusive lock on the folder `dir` (created if absent), held until the returned file is
/// dropped; waits while another fringe process holds it. The folder itself is locked (`flock`),
/// so no lock file is left behind.
pub fn lock_dir(dir: &Path) -> std::io::Result<std::fs::File> {
    std::fs::create_dir_all(dir)?;
    let f = std::fs::File::open(dir)?;
    f.lock()?;
    Ok(f)
}

/// Remove leftover temporary files of interrupted atomic writes in `dir` (not recursive):
/// `.fringe-tmp-*`, and `.tmp*` of versions before the prefix. Call it holding [`lock_dir`].
/// Returns how many were removed.
pub(crate) fn remove_stale_temp_files(dir: &Path) -> std::io::Result<usize> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Ok(0);
    };
    let mut removed = 0;
    for e in rd {
        let e = e?;
        let name = e.file_name();
        let name = name.to_string_lossy();
        if (name.starts_with(TEMP_PREFIX) || name.starts_with(".tmp")) && e.file_type()?.is_file() {
            std::fs::remove_file(e.path())?;
            removed += 1;
        }
    }
    Ok(removed)
}

/// Sync a folder's entries (renames in it) to disk.
fn sync_dir(dir: &Path) -> std::io::Result<()> {
    std::fs::File::open(dir)?.sync_all()
}

/// Finish or undo an interrupted `bless_set` in `golden_dir`: with a commit mark, rename the
/// staged files into place (roll forward); without one, delete the stage (roll back). Also
/// removes stale temporary files. Call it holding [`lock_dir`] on `golden_dir`. Returns whether
/// there was anything to recover.
pub fn recover_bless(golden_dir: &Path) -> std::io::Result<bool> {
    let stage = golden_dir.join(BLESS_STAGE);
    let stale = remove_stale_temp_files(golden_dir)? > 0;
    if !stage.exists() {
        return Ok(stale);
    }
    if let Ok(list) = std::fs::read_to_string(stage.join(BLESS_COMMIT)) {
        for name in list.lines().filter(|l| !l.is_empty()) {
            let staged = stage.join(name);
            if staged.exists() {
                std::fs::rename(&staged, golden_dir.join(name))?;
            }
        }
        sync_dir(golden_dir)?;
    }
    std::fs::remove_dir_all(&stage)?;
    Ok(true)
}

/// Write the golden files `files` (file name, text) into `golden_dir` as one set: stage every
/// file (synced), commit the list, then rename each into place (see the module docs for what a
/// kill leaves). Call it holding [`lock_dir`] on `golden_dir`.
pub(crate) fn bless_set(golden_dir: &Path, files: &[(String, String)]) -> std::io::Result<()> {
    recover_bless(golden_dir)?;
    let stage = golden_dir.join(BLESS_STAGE);
    std::fs::create_dir_all(&stage)?;
    for (name, text) in files {
        write_atomic(&stage.join(name), text.as_bytes())?;
    }
    let list: String = files.iter().map(|(n, _)| format!("{n}\n")).collect();
    // The commit point: from here on the new set is what the golden folder holds.
    write_atomic(&stage.join(BLESS_COMMIT), list.as_bytes())?;
    sync_dir(&stage)?;
    for (name, _) in files {
        std::fs::rename(stage.join(name), golden_dir.join(name))?;
    }
    sync_dir(golden_dir)?;
    std::fs::remove_dir_all(&stage)?;
    Ok(())
}

/// Rows of text fields as CSV text with a header line, written by the `csv` crate (which quotes
/// a field holding a comma, a quote or a line break; the numbers are formatted by the caller so
/// that golden files keep their 17 significant digits).
pub fn csv_text(header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    // Writing into memory cannot fail; a record of the wrong length is a programming error
    // caught by the tests that read these files back.
    let mut put = |fields: &[String]| {
        w.write_record(fields)
            .expect("CSV into memory: records of one length");
    };
    put(&header.iter().map(|h| h.to_string()).collect::<Vec<_>>());
    for r in rows {
        put(&r);
    }
    let bytes = w.into_inner().expect("CSV into memory");
    String::from_utf8(bytes).expect("CSV of UTF-8 fields")
}
