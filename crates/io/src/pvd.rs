//! ParaView collection (`.pvd`) files that tie snapshots to their times.

use std::path::Path;

use crate::atomic::write_atomic;
use crate::number::format_f64;
use crate::IoError;

/// A time series of snapshot files, written as a ParaView `.pvd`
/// collection so that ParaView shows the snapshots as one animated data set.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PvdSeries {
    entries: Vec<(f64, String)>,
}

impl PvdSeries {
    /// An empty series.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a snapshot at simulation time `time` (s), stored in `file`, a
    /// path relative to the directory of the `.pvd` file.
    pub fn push(&mut self, time: f64, file: impl Into<String>) {
        self.entries.push((time, file.into()));
    }

    /// The `(time, relative_file_name)` entries, in the order pushed.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// Number of snapshots in the series.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the series has no snapshots.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The text of the `.pvd` file: one `DataSet` element per entry, times
    /// printed so that they read back exactly, file names XML-escaped.
    pub fn to_xml(&self) -> String {
        let mut xml = String::from(
            "<?xml version=\"1.0\"?>\n\
             <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n\
             \x20 <Collection>\n",
        );
        for (time, file) in &self.entries {
            xml.push_str(&format!(
                "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n",
                format_f64(*time),
                escape_attribute(file)
            ));
        }
        xml.push_str("  </Collection>\n</VTKFile>\n");
        xml
    }

    /// Writes the collection to `path` (atomically), replacing any earlier
    /// version, so it can be rewritten after every snapshot.
    pub fn write(&self, path: &Path) -> Result<(), IoError> {
        write_atomic(path, self.to_xml().as_bytes())
    }
}

/// `s` with the characters that are special inside a double-quoted XML
/// attribute replaced by entities.
pub(crate) fn escape_attribute(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collection_text_lists_every_snapshot_in_order() {
        let mut series = PvdSeries::new();
        assert!(series.is_empty());
        series.push(0.0, "snap_00000000.vti");
        series.push(0.1 + 0.2, "snap_00000010.vti");
        series.push(2.5e-7, "snap_00000020.vti");
        assert_eq!(series.len(), 3);
        assert_eq!(
            series.to_xml(),
            "<?xml version=\"1.0\"?>\n\
             <VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n\
             \x20 <Collection>\n\
             \x20   <DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"snap_00000000.vti\"/>\n\
             \x20   <DataSet timestep=\"0.30000000000000004\" group=\"\" part=\"0\" \
             file=\"snap_00000010.vti\"/>\n\
             \x20   <DataSet timestep=\"2.5e-7\" group=\"\" part=\"0\" \
             file=\"snap_00000020.vti\"/>\n\
             \x20 </Collection>\n\
             </VTKFile>\n"
        );
    }

    #[test]
    fn file_names_are_xml_escaped() {
        let mut series = PvdSeries::new();
        series.push(1.0, "a&b<\"c\">'.vti");
        assert!(series
            .to_xml()
            .contains("file=\"a&amp;b&lt;&quot;c&quot;&gt;&apos;.vti\""));
    }

    #[test]
    fn write_puts_the_text_on_disk() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("series.pvd");
        let mut series = PvdSeries::new();
        series.write(&path).unwrap();
        series.push(1.5, "s.vti");
        series.write(&path).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), series.to_xml());
        assert_eq!(series.entries(), &[(1.5, "s.vti".to_string())]);
    }
}
