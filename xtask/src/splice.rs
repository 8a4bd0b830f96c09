//! `cargo xtask validate --only CASE[,CASE...]`: runs some cases and splices
//! their sections into the existing `docs/validation.md`, so one case can be
//! re-measured without the whole (long) run.
//!
//! A section is the text from a line starting with `## ` to the next such
//! line; it is keyed by its first word after `## ` (`V-TAYLOR`, `V-SOD`,
//! `Throughput`, ...). A re-run section replaces the one with the same key;
//! a new one goes before the `Throughput` section (where the full run puts
//! the validation cases), or at the end. The summary is then rebuilt from
//! every figure-of-merit row of the spliced report (`| what | measured |
//! target | FAIL |`), in the same form the full run writes.

/// The report under the workspace `root`: docs/validation.md.
pub(crate) fn report_path(root: &std::path::Path) -> std::path::PathBuf {
    root.join("docs/validation.md")
}

/// The summary block of a report body: `## Summary`, then the failing
/// figure-of-merit rows of `body`, as `validate` writes it.
pub(crate) fn summary(body: &str) -> String {
    let failures: Vec<String> = body
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line
                .strip_prefix('|')?
                .strip_suffix('|')?
                .split(" | ")
                .map(str::trim)
                .collect();
            match cells.as_slice() {
                [what, measured, target, "FAIL"] => {
                    Some(format!("{what}: {measured} (target {target})"))
                }
                _ => None,
            }
        })
        .collect();
    let mut s = String::from("## Summary\n\n");
    if failures.is_empty() {
        s.push_str("All targets met.\n\n");
    } else {
        s.push_str("Targets not met:\n\n");
        for f in &failures {
            s.push_str("- ");
            s.push_str(f);
            s.push('\n');
        }
        s.push('\n');
    }
    s
}

/// Splits `text` into its `## ` sections (each with its heading line and a
/// trailing newline), keyed by the heading's first word. Text before the
/// first heading is dropped.
fn sections(text: &str) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = Vec::new();
    for line in text.split_inclusive('\n') {
        if let Some(heading) = line.strip_prefix("## ") {
            let key = heading.split_whitespace().next().unwrap_or("").to_string();
            out.push((key, line.to_string()));
        } else if let Some((_, s)) = out.last_mut() {
            s.push_str(line);
        }
    }
    out
}

/// `existing` (a whole report) with the sections of `new_body` spliced in
/// and its summary rebuilt; `preamble` is used when `existing` has no
/// `## Summary` heading (no report yet).
pub(crate) fn splice(existing: &str, new_body: &str, preamble: &str) -> String {
    let (head, old) = match existing.find("## Summary") {
        Some(i) => {
            let after = &existing[i..];
            let body_start = after.find("\n## ").map_or(after.len(), |j| j + 1);
            (existing[..i].to_string(), after[body_start..].to_string())
        }
        None => (preamble.to_string(), String::new()),
    };
    let mut all = sections(&old);
    for (key, text) in sections(new_body) {
        if let Some(slot) = all.iter_mut().find(|(k, _)| *k == key) {
            slot.1 = text;
        } else {
            let at = all
                .iter()
                .position(|(k, _)| k == "Throughput")
                .unwrap_or(all.len());
            all.insert(at, (key, text));
        }
    }
    let body: String = all.into_iter().map(|(_, s)| s).collect();
    format!("{head}{}{body}", summary(&body))
}

#[cfg(test)]
mod tests {
    use super::*;

    const BODY: &str = "## V-A — first\n\ntext a\n\n| figure of merit | measured | target | verdict |\n|---|---:|---|---|\n| A one | 1 | ≤ 2 | PASS |\n| A two | 3 | ≤ 2 | FAIL |\n\n## Throughput — last\n\n| T | 5 | ≥ 9 | FAIL |\n";

    fn report(body: &str) -> String {
        format!("# Report\n\nMachine: 2.\n\n{}{body}", summary(body))
    }

    #[test]
    fn summary_lists_the_failing_four_column_rows_as_validate_writes_them() {
        assert_eq!(
            summary(BODY),
            "## Summary\n\nTargets not met:\n\n- A two: 3 (target ≤ 2)\n- T: 5 (target ≥ 9)\n\n"
        );
        assert_eq!(
            summary("| a | b | c | PASS |\n| x | FAIL |\n"),
            "## Summary\n\nAll targets met.\n\n"
        );
    }

    #[test]
    fn a_rerun_section_replaces_its_namesake_and_the_summary_follows() {
        let new = "## V-A — first, again\n\n| A two | 1 | ≤ 2 | PASS |\n\n";
        let got = splice(&report(BODY), new, "unused");
        let want_body = format!("{new}## Throughput — last\n\n| T | 5 | ≥ 9 | FAIL |\n");
        assert_eq!(got, report(&want_body));
        assert!(!got.contains("A one"));
    }

    #[test]
    fn a_new_section_goes_before_throughput_and_splicing_twice_changes_nothing() {
        let new = "## V-NEW — case\n\n| N | 7 | ≤ 1 | FAIL |\n\n";
        let once = splice(&report(BODY), new, "unused");
        let (a, t) = BODY.split_at(BODY.find("## Throughput").unwrap());
        assert_eq!(once, report(&format!("{a}{new}{t}")));
        assert!(once.contains("- N: 7 (target ≤ 1)\n"));
        assert_eq!(splice(&once, new, "unused"), once);
    }

    #[test]
    fn without_a_report_the_preamble_starts_a_new_one() {
        let new = "## V-NEW — case\n\n| N | 7 | ≤ 9 | PASS |\n";
        assert_eq!(
            splice("", new, "# Report\n\n"),
            format!("# Report\n\n## Summary\n\nAll targets met.\n\n{new}")
        );
    }
}
