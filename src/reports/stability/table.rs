//! The printed table, the per-group summary, the closing line, and the CSV file.

use super::case::{Case, Report};

/// Column widths are fitted to the contents; long texts are not cut.
fn render_rows(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.chars().count());
        }
    }
    let line = |cells: &[String]| {
        let mut s = String::new();
        for (k, (cell, w)) in cells.iter().zip(&widths).enumerate() {
            let pad = w - cell.chars().count();
            // Text columns left-aligned, numbers right-aligned.
            let numeric = cell.starts_with(|c: char| c.is_ascii_digit() || c == '-') && k > 2;
            if numeric {
                s.push_str(&" ".repeat(pad));
                s.push_str(cell);
            } else {
                s.push_str(cell);
                s.push_str(&" ".repeat(pad));
            }
            if k + 1 < cells.len() {
                s.push_str("  ");
            }
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(&header.iter().map(|h| h.to_string()).collect::<Vec<_>>());
    for row in rows {
        out.push_str(&line(row));
    }
    out
}

fn rel_text(c: &Case) -> String {
    c.rel_err.map_or("-".to_string(), |r| format!("{r:.1e}"))
}

/// The full case table, followed by the list of singular-case reasons it refers to.
pub fn case_table(report: &Report) -> String {
    let mut reasons: Vec<String> = Vec::new();
    let rows: Vec<Vec<String>> = report
        .cases
        .iter()
        .map(|c| {
            let status = match (&c.failure, &c.singular) {
                (Some(f), _) => format!("FAIL: {f}"),
                (None, Some(reason)) => {
                    let k = reasons.iter().position(|r| r == reason).unwrap_or_else(|| {
                        reasons.push(reason.clone());
                        reasons.len() - 1
                    });
                    format!("ok, singular [{}]", k + 1)
                }
                (None, None) => "ok".to_string(),
            };
            vec![
                c.group.to_string(),
                c.name.clone(),
                c.inputs.clone(),
                c.f32_value.clone(),
                c.f64_value.clone(),
                rel_text(c),
                c.evals.to_string(),
                c.nan.to_string(),
                c.inf.to_string(),
                c.neg.to_string(),
                status,
            ]
        })
        .collect();
    let header = [
        "group", "case", "inputs", "f32", "f64", "rel.err", "evals", "NaN", "Inf", "neg", "result",
    ];
    let mut out = render_rows(&header, &rows);
    if !reasons.is_empty() {
        out.push_str("\nsingular cases (the f32-vs-f64 tolerance does not apply; the documented value is checked):\n");
        for (k, r) in reasons.iter().enumerate() {
            out.push_str(&format!("[{}] {r}\n", k + 1));
        }
    }
    out
}

/// The worst f32-vs-f64 relative error over non-singular cases, with its case.
pub fn worst(cases: &[Case]) -> Option<(f64, &Case)> {
    cases
        .iter()
        .filter(|c| c.singular.is_none())
        .filter_map(|c| c.rel_err.map(|r| (r, c)))
        .max_by(|a, b| a.0.total_cmp(&b.0))
}

/// One line per group: cases, failures, evaluations, NaN/Inf/negative, worst relative error.
pub fn summary_table(report: &Report) -> String {
    let mut groups: Vec<&'static str> = Vec::new();
    for c in &report.cases {
        if !groups.contains(&c.group) {
            groups.push(c.group);
        }
    }
    let rows: Vec<Vec<String>> = groups
        .iter()
        .map(|g| {
            let cs: Vec<Case> = report.cases.iter().filter(|c| c.group == *g).cloned().collect();
            let sum = |f: fn(&Case) -> u64| cs.iter().map(f).sum::<u64>();
            vec![
                g.to_string(),
                cs.len().to_string(),
                cs.iter().filter(|c| !c.passed()).count().to_string(),
                cs.iter().filter(|c| c.singular.is_some()).count().to_string(),
                sum(|c| c.evals).to_string(),
                sum(|c| c.nan).to_string(),
                sum(|c| c.inf).to_string(),
                sum(|c| c.neg).to_string(),
                worst(&cs).map_or("-".to_string(), |(r, _)| format!("{r:.1e}")),
            ]
        })
        .collect();
    let header = [
        "group",
        "cases",
        "failures",
        "singular",
        "evals",
        "NaN",
        "Inf",
        "neg",
        "worst rel.err",
    ];
    render_rows(&header, &rows)
}

/// `N cases, F failures, worst relative error E (case)`.
pub fn summary_line(report: &Report) -> String {
    let worst = worst(&report.cases).map_or("-".to_string(), |(r, c)| format!("{r:.1e} ({}: {})", c.name, c.inputs));
    format!(
        "{} cases, {} failures, worst relative error {worst}",
        report.cases.len(),
        report.failures()
    )
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Every case as CSV, one row each, with a header.
pub fn csv(report: &Report) -> String {
    let mut out = String::from("group,case,inputs,f32,f64,rel_err,evals,nan,inf,neg,singular,failure\n");
    for c in &report.cases {
        let fields = [
            c.group.to_string(),
            c.name.clone(),
            c.inputs.clone(),
            c.f32_value.clone(),
            c.f64_value.clone(),
            c.rel_err.map_or(String::new(), |r| format!("{r:e}")),
            c.evals.to_string(),
            c.nan.to_string(),
            c.inf.to_string(),
            c.neg.to_string(),
            c.singular.clone().unwrap_or_default(),
            c.failure.clone().unwrap_or_default(),
        ];
        let line: Vec<String> = fields.iter().map(|f| csv_field(f)).collect();
        out.push_str(&line.join(","));
        out.push('\n');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reports::stability::case::num;

    fn case(name: &str, rel: Option<f64>, singular: bool, fail: bool) -> Case {
        let mut c = Case::new("brdf", name, "a, b");
        c.rel_err = rel;
        c.f32_value = num(1.5);
        if singular {
            c.singular = Some("because".into());
        }
        if fail {
            c.fail("too far");
        }
        c
    }

    #[test]
    fn summary_line_counts_failures_and_ignores_singular_errors() {
        let report = Report {
            cases: vec![
                case("x", Some(1e-6), false, false),
                case("y", Some(0.5), true, false),
                case("z", Some(2e-5), false, true),
            ],
            notes: vec![],
        };
        let line = summary_line(&report);
        assert!(
            line.starts_with("3 cases, 1 failures, worst relative error 2.0e-5 (z: a, b)"),
            "{line}"
        );
        let table = case_table(&report);
        assert!(table.contains("ok, singular [1]") && table.contains("[1] because") && table.contains("FAIL: too far"));
        assert!(summary_table(&report).lines().nth(1).unwrap().starts_with("brdf"));
    }

    #[test]
    fn csv_quotes_fields_with_commas() {
        let report = Report {
            cases: vec![case("x", None, false, false)],
            notes: vec![],
        };
        let text = csv(&report);
        assert_eq!(text.lines().count(), 2);
        assert!(
            text.lines().nth(1).unwrap().starts_with("brdf,x,\"a, b\",1.5,"),
            "{text}"
        );
    }
}
