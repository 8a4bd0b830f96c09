//! Small comma-separated tables of numbers: gauge histories, line-outs and
//! conservation histories, and a reader for such tables.
//!
//! Every file has one header line of column names followed by one line per
//! row. Numbers are printed with [`format_f64`], so they read back to the
//! identical `f64`. Column names may not contain commas, quotes or line
//! breaks (nothing is quoted).

use std::fmt::Write as _;
use std::path::Path;

use brisance_core::ConservationTotals;

use crate::atomic::write_atomic;
use crate::number::format_f64;
use crate::IoError;

/// What [`read_csv`] calls its files in errors.
const KIND: &str = "CSV table of numbers";

/// Writes a gauge history: header `time,<field>,...`, then one line per
/// `(time, values)` row, `values` in the order of `fields`.
pub fn write_gauge_csv(
    path: &Path,
    fields: &[String],
    rows: &[(f64, Vec<f64>)],
) -> Result<(), IoError> {
    let header = prefixed_header(&["time"], fields);
    let mut table = Table::new(path, &header)?;
    for (time, values) in rows {
        table.row(&[*time], values)?;
    }
    table.write()
}

/// Writes a line-out: header `x,y,z,<field>,...`, then for each `k` one line
/// with `points[k]` followed by `values[k]` (the field values there, in the
/// order of `fields`).
pub fn write_lineout_csv(
    path: &Path,
    fields: &[String],
    points: &[[f64; 3]],
    values: &[Vec<f64>],
) -> Result<(), IoError> {
    if points.len() != values.len() {
        return Err(IoError::invalid_input(
            path,
            format!(
                "{} line-out points but {} rows of values",
                points.len(),
                values.len()
            ),
        ));
    }
    let header = prefixed_header(&["x", "y", "z"], fields);
    let mut table = Table::new(path, &header)?;
    for (point, row) in points.iter().zip(values) {
        table.row(point, row)?;
    }
    table.write()
}

/// Writes a conservation history: header
/// `time,mass,momentum_x,momentum_y,momentum_z,energy`, then one line per
/// `(time, totals)` row.
pub fn write_conservation_csv(
    path: &Path,
    rows: &[(f64, ConservationTotals)],
) -> Result<(), IoError> {
    conservation_table(path, rows, None)
}

/// Writes a conservation history with the work of the external forces:
/// the columns of [`write_conservation_csv`] followed by `external_work`
/// (W, J, done on the domain since the start) and
/// `energy_minus_external_work` (E − W, which the external forces leave
/// unchanged). `work[k]` belongs to `rows[k]`.
pub fn write_conservation_csv_with_work(
    path: &Path,
    rows: &[(f64, ConservationTotals)],
    work: &[f64],
) -> Result<(), IoError> {
    if work.len() != rows.len() {
        return Err(IoError::invalid_input(
            path,
            format!(
                "{} conservation rows but {} external-work values",
                rows.len(),
                work.len()
            ),
        ));
    }
    conservation_table(path, rows, Some(work))
}

fn conservation_table(
    path: &Path,
    rows: &[(f64, ConservationTotals)],
    work: Option<&[f64]>,
) -> Result<(), IoError> {
    let mut header: Vec<String> = [
        "time",
        "mass",
        "momentum_x",
        "momentum_y",
        "momentum_z",
        "energy",
    ]
    .map(String::from)
    .to_vec();
    if work.is_some() {
        header.push("external_work".into());
        header.push("energy_minus_external_work".into());
    }
    let mut table = Table::new(path, &header)?;
    for (k, (time, t)) in rows.iter().enumerate() {
        let [px, py, pz] = t.momentum;
        match work {
            Some(w) => table.row(
                &[*time, t.mass, px, py, pz, t.energy],
                &[w[k], t.energy - w[k]],
            )?,
            None => table.row(&[*time, t.mass, px, py, pz, t.energy], &[])?,
        }
    }
    table.write()
}

/// Reads a table written by this module (or any header-plus-numbers CSV):
/// returns the column names and the rows of numbers. Blank lines are
/// skipped; a missing header, a row of the wrong width or a cell that is not
/// a number is an error naming the file, line and column.
pub fn read_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), IoError> {
    let bytes = std::fs::read(path).map_err(|e| IoError::read(path, e))?;
    let text = String::from_utf8(bytes)
        .map_err(|e| IoError::malformed(path, KIND, format!("not UTF-8 text: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, line)| !line.trim().is_empty());
    let (_, header_line) = lines
        .next()
        .ok_or_else(|| IoError::malformed(path, KIND, "the file has no header line"))?;
    let header: Vec<String> = header_line
        .split(',')
        .map(|name| name.trim().to_string())
        .collect();
    let mut rows = Vec::new();
    for (index, line) in lines {
        let line_number = index + 1;
        let cells: Vec<&str> = line.split(',').collect();
        if cells.len() != header.len() {
            return Err(IoError::malformed(
                path,
                KIND,
                format!(
                    "line {line_number} has {} values but the header has {} columns",
                    cells.len(),
                    header.len()
                ),
            ));
        }
        let row = cells
            .iter()
            .zip(&header)
            .map(|(cell, name)| {
                cell.trim().parse::<f64>().map_err(|_| {
                    IoError::malformed(
                        path,
                        KIND,
                        format!(
                            "line {line_number}, column `{name}`: `{}` is not a number",
                            cell.trim()
                        ),
                    )
                })
            })
            .collect::<Result<Vec<f64>, IoError>>()?;
        rows.push(row);
    }
    Ok((header, rows))
}

/// `fixed` column names followed by `fields`.
fn prefixed_header(fixed: &[&str], fields: &[String]) -> Vec<String> {
    fixed
        .iter()
        .map(|s| s.to_string())
        .chain(fields.iter().cloned())
        .collect()
}

/// A table being assembled in memory before one atomic write.
struct Table<'a> {
    path: &'a Path,
    columns: usize,
    text: String,
}

impl<'a> Table<'a> {
    /// Starts a table with the given column names, checking that each can be
    /// stored unquoted.
    fn new(path: &'a Path, header: &[String]) -> Result<Self, IoError> {
        for name in header {
            if name.is_empty() || name.contains([',', '"', '\n', '\r']) {
                return Err(IoError::invalid_input(
                    path,
                    format!(
                        "column name {name:?} is empty or contains a comma, quote or line break"
                    ),
                ));
            }
        }
        let mut text = header.join(",");
        text.push('\n');
        Ok(Self {
            path,
            columns: header.len(),
            text,
        })
    }

    /// Appends the row `lead` followed by `rest`.
    fn row(&mut self, lead: &[f64], rest: &[f64]) -> Result<(), IoError> {
        let width = lead.len() + rest.len();
        if width != self.columns {
            return Err(IoError::invalid_input(
                self.path,
                format!(
                    "line {} would have {width} values but the header has {} columns",
                    self.text.lines().count() + 1,
                    self.columns
                ),
            ));
        }
        for (i, x) in lead.iter().chain(rest).enumerate() {
            if i > 0 {
                self.text.push(',');
            }
            // Writing to a String cannot fail.
            let _ = write!(self.text, "{}", format_f64(*x));
        }
        self.text.push('\n');
        Ok(())
    }

    /// Writes the table to its path atomically.
    fn write(self) -> Result<(), IoError> {
        write_atomic(self.path, self.text.as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    fn bits(rows: &[Vec<f64>]) -> Vec<Vec<u64>> {
        rows.iter()
            .map(|r| r.iter().map(|x| x.to_bits()).collect())
            .collect()
    }

    #[test]
    fn gauge_csv_has_time_header_and_round_trips_exact_values() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("gauge.csv");
        let fields = names(&["pressure", "density"]);
        let rows = vec![
            (0.0, vec![101325.0, 1.225]),
            (1e-6, vec![0.1 + 0.2, 1e-300]),
            (2.5e-6, vec![-3.75e12, f64::MIN_POSITIVE]),
        ];
        write_gauge_csv(&path, &fields, &rows).unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "time,pressure,density\n\
             0,101325,1.225\n\
             1e-6,0.30000000000000004,1e-300\n\
             2.5e-6,-3750000000000,2.2250738585072014e-308\n"
        );
        let (header, read) = read_csv(&path).unwrap();
        assert_eq!(header, names(&["time", "pressure", "density"]));
        let expected: Vec<Vec<f64>> = rows
            .iter()
            .map(|(t, v)| std::iter::once(*t).chain(v.iter().copied()).collect())
            .collect();
        assert_eq!(bits(&read), bits(&expected));
    }

    #[test]
    fn lineout_csv_starts_rows_with_coordinates() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("line.csv");
        let fields = names(&["pressure"]);
        let points = [[0.05, 0.0, -1.0], [0.15, 0.0, -1.0]];
        let values = [vec![2.0], vec![1.0 / 3.0]];
        write_lineout_csv(&path, &fields, &points, &values).unwrap();
        let (header, rows) = read_csv(&path).unwrap();
        assert_eq!(header, names(&["x", "y", "z", "pressure"]));
        assert_eq!(
            bits(&rows),
            bits(&[vec![0.05, 0.0, -1.0, 2.0], vec![0.15, 0.0, -1.0, 1.0 / 3.0]])
        );
    }

    #[test]
    fn conservation_csv_has_one_column_per_total() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("conservation.csv");
        let totals = ConservationTotals {
            mass: 1.5,
            momentum: [0.1 + 0.2, -0.0, 1e-300],
            energy: 2.0e9,
        };
        write_conservation_csv(&path, &[(0.25, totals)]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "time,mass,momentum_x,momentum_y,momentum_z,energy\n\
             0.25,1.5,0.30000000000000004,-0,1e-300,2000000000\n"
        );
        let (_, rows) = read_csv(&path).unwrap();
        assert_eq!(
            bits(&rows),
            bits(&[vec![0.25, 1.5, 0.1 + 0.2, -0.0, 1e-300, 2.0e9]])
        );
    }

    #[test]
    fn conservation_csv_with_work_adds_work_and_the_balance() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("conservation.csv");
        let totals = |energy| ConservationTotals {
            mass: 2.0,
            momentum: [0.5, 0.0, 0.0],
            energy,
        };
        let rows = [(0.0, totals(10.0)), (1.0, totals(10.75))];
        write_conservation_csv_with_work(&path, &rows, &[0.0, 0.5]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "time,mass,momentum_x,momentum_y,momentum_z,energy,external_work,energy_minus_external_work\n\
             0,2,0.5,0,0,10,0,10\n\
             1,2,0.5,0,0,10.75,0.5,10.25\n"
        );
        let err = write_conservation_csv_with_work(&path, &rows, &[0.0]).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
        assert!(
            err.to_string().contains("2 conservation rows but 1"),
            "{err}"
        );
    }

    #[test]
    fn empty_history_is_just_the_header() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("empty.csv");
        write_conservation_csv(&path, &[]).unwrap();
        let (header, rows) = read_csv(&path).unwrap();
        assert_eq!(header.len(), 6);
        assert!(rows.is_empty());
    }

    #[test]
    fn inconsistent_rows_are_rejected_before_writing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.csv");
        let fields = names(&["a", "b"]);
        let err = write_gauge_csv(&path, &fields, &[(0.0, vec![1.0])]).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
        let err = write_lineout_csv(&path, &fields, &[[0.0; 3]], &[]).unwrap_err();
        assert!(matches!(err, IoError::InvalidInput { .. }), "{err:?}");
        let err = write_gauge_csv(&path, &names(&["a,b"]), &[]).unwrap_err();
        assert!(err.to_string().contains("comma"), "{err}");
        assert!(!path.exists());
    }

    #[test]
    fn reader_reports_line_and_column_of_bad_cells() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("hand.csv");
        std::fs::write(&path, "t, p\r\n\n1, 2\r\n3,x\n").unwrap();
        let err = read_csv(&path).unwrap_err();
        let text = err.to_string();
        assert!(text.starts_with(&path.display().to_string()), "{text}");
        assert!(text.contains("line 4, column `p`: `x`"), "{text}");

        std::fs::write(&path, "t,p\n1,2,3\n").unwrap();
        let text = read_csv(&path).unwrap_err().to_string();
        assert!(text.contains("line 2 has 3 values"), "{text}");

        std::fs::write(&path, "\n\n").unwrap();
        let text = read_csv(&path).unwrap_err().to_string();
        assert!(text.contains("no header line"), "{text}");
    }

    #[test]
    fn reader_accepts_crlf_and_spaces() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("hand.csv");
        std::fs::write(&path, "t, p\r\n1, 2.5\r\n").unwrap();
        let (header, rows) = read_csv(&path).unwrap();
        assert_eq!(header, names(&["t", "p"]));
        assert_eq!(rows, vec![vec![1.0, 2.5]]);
    }

    #[test]
    fn reading_a_missing_file_names_it() {
        let path = Path::new("/nonexistent/brisance/gauge.csv");
        let err = read_csv(path).unwrap_err();
        assert!(matches!(err, IoError::Read { .. }), "{err:?}");
        assert!(err
            .to_string()
            .starts_with("cannot read /nonexistent/brisance/gauge.csv: "));
    }
}
