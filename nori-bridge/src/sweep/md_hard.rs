//! The hard-case section of docs/reports/speed-vs-error.md: one table of leaks,
//! false hits and wrong prims per configuration and case, with Embree,
//! Embree ROBUST and the f64 reference; then every non-zero cell of a
//! watertight + conservative configuration, which the issue wants at zero.

use crate::sweep::input::HardIn;
use crate::sweep::report::Report;

const REF_COLUMNS: [(&str, &str); 3] = [
    ("embree", "Embree"),
    ("robust", "Embree ROBUST"),
    ("double", "f64 reference"),
];

fn cell(h: &HardIn) -> String {
    let mut s = format!("{}/{}/{}", h.leaks, h.false_hits, h.wrong_prims);
    if h.flagged != 0 {
        s.push_str(&format!(" (flagged {})", h.flagged));
    }
    s
}

fn dirty(h: &HardIn) -> bool {
    h.leaks + h.false_hits + h.wrong_prims != 0
}

/// Lines of the section (no trailing newline on each).
pub fn section(r: &Report, notes: &std::path::Path) -> Vec<String> {
    let mut out = vec!["## Hard cases".to_string(), String::new()];
    if r.hard_references.is_empty() {
        out.push("The sweep ran no hard case (no run has a `hard_case`).".into());
        return out;
    }
    out.push(
        "Cell = leaks / false hits / wrong prims (and `flagged` rays when the hardware raised its error flag), as scored by \
         `nori-bridge hard-score`. A leak is a ray that escapes a closed surface it starts inside."
            .into(),
    );
    out.push(String::new());
    // One row per configuration (and per reference), one column per case:
    // 24+ configurations fit down the page, 8 cases across it.
    let cases: Vec<&String> = r.hard_references.keys().collect();
    let mut head = "| configuration |".to_string();
    let mut rule = "| --- |".to_string();
    for case in &cases {
        head.push_str(&format!(
            " {case} ({} rays) |",
            r.hard_references[*case]["double"].rays
        ));
        rule.push_str(" --- |");
    }
    out.push(head);
    out.push(rule);
    let mut bad = Vec::new();
    for p in &r.points {
        let mut row = format!("| {} |", p.name);
        for case in &cases {
            let runs = p
                .runs
                .iter()
                .filter(|x| x.hard_case.as_deref() == Some(case.as_str()));
            let cells: Vec<String> = runs
                .filter_map(|x| x.hard.as_ref())
                .inspect(|h| {
                    if p.config.triangle == "watertight"
                        && p.config.rounding == "conservative"
                        && dirty(h)
                    {
                        bad.push(format!(
                            "- `{case}` on `{}`: {} leaks, {} false hits, {} wrong prims",
                            p.name, h.leaks, h.false_hits, h.wrong_prims
                        ));
                    }
                })
                .map(cell)
                .collect();
            row.push_str(&format!(" {} |", cells.join("; ")));
        }
        out.push(row);
    }
    for (key, title) in REF_COLUMNS {
        let mut row = format!("| {title} |");
        for case in &cases {
            row.push_str(&format!(" {} |", cell(&r.hard_references[*case][key])));
        }
        out.push(row);
    }
    out.push(String::new());
    out.push("### Watertight + conservative configurations".into());
    out.push(String::new());
    let wc = r
        .points
        .iter()
        .filter(|p| p.config.triangle == "watertight" && p.config.rounding == "conservative")
        .count();
    if wc == 0 {
        out.push("The sweep has no watertight + conservative configuration.".into());
    } else if bad.is_empty() {
        out.push(format!("All {wc} watertight + conservative configurations have zero leaks, false hits and wrong prims on every hard case."));
    } else {
        out.push(format!(
            "**Generated placeholder:** {} non-zero cell(s) for watertight + conservative configurations, where the goal is zero. \
             Each needs an explanation in the hand-written notes (`{}`, included at the end):",
            bad.len(),
            notes.display()
        ));
        out.push(String::new());
        out.extend(bad);
    }
    out
}
