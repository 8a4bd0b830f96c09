//! The rows of cases a run leaves out, kept from the report it replaces:
//! E-PLATE's cases take 25–45 min each on two cores and E-SLAB's charges
//! about 5 min, so they are often run a few at a time (`PLATE_CASES`,
//! `SLAB_CHARGES`), and the section each run writes keeps the other
//! cases' table rows, notes and verdicts as the earlier report had them
//! (and says which).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::splice::report_path;
use crate::Report;

/// What an earlier report's section said about one case, verbatim: its
/// table rows (one per grid it ran on), its note lines and its
/// figure-of-merit rows (what, measured, target, passed).
#[derive(Debug, Default, Clone, PartialEq)]
pub(crate) struct Kept {
    pub rows: Vec<String>,
    pub notes: Vec<String>,
    pub targets: Vec<(String, String, String, bool)>,
}

impl Kept {
    /// Writes its table rows into `md`, in the order the earlier section
    /// had them.
    pub fn write_rows(&self, md: &mut String) {
        for row in &self.rows {
            let _ = writeln!(md, "{row}");
        }
    }
}

/// After a section's table: the sentence naming what it kept (`what`:
/// "case 3", "4 kg, 10 kg") and the run switch (`PLATE_CASES`,
/// `SLAB_CHARGES`) that left it out.
pub(crate) fn write_kept_sentence(md: &mut String, what: &str, switch: &str) {
    let _ = writeln!(
        md,
        "\nKept from the report this section replaced: {what} (rows, notes and verdicts as that report had them), left out by `{switch}` in the run that wrote this section."
    );
}

/// The kept cases' notes into `md`, each as a paragraph.
pub(crate) fn write_kept_notes<'a>(md: &mut String, kept: impl IntoIterator<Item = &'a Kept>) {
    for note in kept.into_iter().flat_map(|k| &k.notes) {
        let _ = writeln!(md, "\n{note}");
    }
}

/// The kept cases' figures of merit into `report`, verdicts as they were.
pub(crate) fn add_kept_verdicts<'a>(report: &mut Report, kept: impl IntoIterator<Item = &'a Kept>) {
    for (what, measured, target, ok) in kept.into_iter().flat_map(|k| &k.targets) {
        report.target(what, measured.clone(), target, *ok);
    }
}

/// [`kept_cases`] of the report under `root` (docs/validation.md) as it
/// stands: read it before the run's first splice rewrites the section.
/// Nothing is kept where there is no report yet.
pub(crate) fn kept_in_report(
    root: &Path,
    heading: &str,
    target_prefix: &str,
    note_prefix: &str,
) -> BTreeMap<String, Kept> {
    let previous = std::fs::read_to_string(report_path(root)).unwrap_or_default();
    kept_cases(&previous, heading, target_prefix, note_prefix)
}

/// The case a row label starts with: its leading number ("4" of
/// "4 kg: …" or "1 (h 5 mm)", "2.5" of "2.5 kg").
fn case_of(label: &str) -> Option<String> {
    let number: String = label
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    number.parse::<f64>().is_ok().then_some(number)
}

/// The cells of a markdown table row, trimmed.
fn cells(line: &str) -> Vec<&str> {
    line.trim()
        .trim_start_matches('|')
        .trim_end_matches('|')
        .split('|')
        .map(str::trim)
        .collect()
}

/// The cases of the section whose heading starts with `heading` in
/// `report` (a whole report's text), by the number that starts their
/// label: the rows of its case table (first cell the label), its notes
/// (lines `note_prefix` + label + ": …") and its figure-of-merit rows
/// (first cell `target_prefix` + label + …). Empty where the report has no
/// such section.
fn kept_cases(
    report: &str,
    heading: &str,
    target_prefix: &str,
    note_prefix: &str,
) -> BTreeMap<String, Kept> {
    let mut kept: BTreeMap<String, Kept> = BTreeMap::new();
    let start = if report.starts_with(heading) {
        Some(0)
    } else {
        report.find(&format!("\n{heading}")).map(|i| i + 1)
    };
    let Some(start) = start else {
        return kept;
    };
    let body = &report[start..];
    let end = body[1..].find("\n## ").map_or(body.len(), |i| i + 2);
    for line in body[..end].lines().skip(1) {
        if line.starts_with('|') {
            let c = cells(line);
            if let Some(rest) = c[0].strip_prefix(target_prefix) {
                let (Some(id), 4) = (case_of(rest), c.len()) else {
                    continue;
                };
                kept.entry(id).or_default().targets.push((
                    c[0].to_string(),
                    c[1].to_string(),
                    c[2].to_string(),
                    c[3] == "PASS",
                ));
            } else if let Some(id) = case_of(c[0]) {
                kept.entry(id).or_default().rows.push(line.to_string());
            }
        } else if let Some(rest) = line.strip_prefix(note_prefix) {
            if let (Some(id), true) = (case_of(rest), rest.contains(": ")) {
                kept.entry(id).or_default().notes.push(line.to_string());
            }
        }
    }
    // A case the earlier section only named in a note or a verdict has no
    // row to keep: it was not run there either.
    kept.retain(|_, k| !k.rows.is_empty());
    kept
}

#[cfg(test)]
mod tests {
    use super::kept_cases;

    const REPORT: &str = "# Report\n\n## E-PLATE — quarter\n\nIntro.\n\n\
| case | scale | δ/t measured |\n|---|---:|---:|\n\
| 1 | 4 | 2.61 |\n| 2 | 2 | 2.62 |\n| 3 | 1 | not run |\n\n\
Case 1: remap ok; the centre is 16 particles.\n\n\
Case 2: remap ok; the centre is 16 particles.\n\n\
| figure of merit | measured | target | verdict |\n|---|---:|---|---|\n\
| E-PLATE case 1 δ/t vs experiment 2.60 | 2.61 (+0.3 %) | within 10 % | PASS |\n\
| E-PLATE case 2 δ/t vs experiment 2.70 | 2.31 (-14.4 %) | within 10 % | FAIL |\n\n\
## E-PLATE-RZ — rings\n\n\
| case | scale | δ/t measured |\n|---|---:|---:|\n\
| 1 | 4 | 2.78 |\n| 1 (h 5 mm) | 4 | 2.89 |\n\n\
Case 1 (h 5 mm): remap ok.\n\n\
| E-PLATE-RZ case 1 δ/t vs experiment 2.60 | 2.78 (+6.9 %) | within 10 % | PASS |\n\n\
## E-SLAB — slab\n\n| 1 | 9 |\n";

    #[test]
    fn the_quarters_rows_notes_and_verdicts_are_kept_by_case() {
        let k = kept_cases(REPORT, "## E-PLATE — ", "E-PLATE case ", "Case ");
        // Case 3's row says "not run" and is kept as such; nothing of the
        // r–z section or of E-SLAB leaks in.
        assert_eq!(k.keys().collect::<Vec<_>>(), ["1", "2", "3"]);
        assert_eq!(k["1"].rows, ["| 1 | 4 | 2.61 |"]);
        assert_eq!(
            k["1"].notes,
            ["Case 1: remap ok; the centre is 16 particles."]
        );
        assert_eq!(
            k["2"].targets,
            [(
                "E-PLATE case 2 δ/t vs experiment 2.70".to_string(),
                "2.31 (-14.4 %)".to_string(),
                "within 10 %".to_string(),
                false
            )]
        );
        assert!(k["1"].targets[0].3);
        assert!(k["3"].notes.is_empty() && k["3"].targets.is_empty());
    }

    #[test]
    fn the_rz_sections_h_sequence_rows_belong_to_their_case() {
        let k = kept_cases(REPORT, "## E-PLATE-RZ — ", "E-PLATE-RZ case ", "Case ");
        assert_eq!(k.len(), 1);
        assert_eq!(
            k["1"].rows,
            ["| 1 | 4 | 2.78 |", "| 1 (h 5 mm) | 4 | 2.89 |"]
        );
        assert_eq!(k["1"].notes, ["Case 1 (h 5 mm): remap ok."]);
        assert_eq!(k["1"].targets.len(), 1);
    }

    #[test]
    fn the_slabs_charges_are_kept_by_their_mass() {
        let report = "## E-SLAB — slab\n\nIntro: text.\n\n\
| W (kg TNT) | D measured (mm) |\n|---:|---:|\n| 2 | 0 |\n| 4 | 0 |\n| 10 | 0 |\n| 20 | not run |\n\n\
2 kg: remap 1D: r_c 66.4 mm; the run reached its end time 500.0 µs.\n\n\
10 kg: remap 1D: r_c 113.6 mm; the run reached its end time 500.0 µs.\n\n\
| figure of merit | measured | target | verdict |\n|---|---:|---|---|\n\
| E-SLAB 2 kg crushing D vs eq 67 219 mm | 0 mm (-100.0 %) | within 20 % | FAIL |\n\
| E-SLAB 10 kg crushing D vs test 300 mm | 0 mm (-100.0 %) | within 20 % | FAIL |\n\
| E-SLAB 10 kg crushing D vs eq 67 304 mm | 0 mm (-100.0 %) | within 20 % | FAIL |\n";
        let k = kept_cases(report, "## E-SLAB — ", "E-SLAB ", "");
        assert_eq!(k.keys().collect::<Vec<_>>(), ["10", "2", "20", "4"]);
        assert_eq!(k["10"].rows, ["| 10 | 0 |"]);
        assert_eq!(
            k["10"].notes,
            ["10 kg: remap 1D: r_c 113.6 mm; the run reached its end time 500.0 µs."]
        );
        assert_eq!(k["10"].targets.len(), 2);
        assert!(!k["10"].targets[1].3);
        assert!(k["4"].notes.is_empty() && k["4"].targets.is_empty());
    }

    #[test]
    fn no_report_or_no_section_keeps_nothing() {
        assert!(kept_cases("", "## E-PLATE — ", "E-PLATE case ", "Case ").is_empty());
        assert!(kept_cases(
            "# Report\n\n## V-SOD — x\n| 1 | 2 |\n",
            "## E-PLATE — ",
            "E-PLATE case ",
            "Case "
        )
        .is_empty());
    }
}
