//! hard-cases and hard-score through the binary: the JSON keys the sweep
//! reads, and a malformed expect.csv named with file and line.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bridge(args: &[&str]) -> std::process::Output {
    Command::new(PathBuf::from(env!("CARGO_BIN_EXE_nori-bridge")))
        .args(args)
        .output()
        .unwrap()
}

fn ok(args: &[&str]) {
    let out = bridge(args);
    assert!(
        out.status.success(),
        "nori-bridge {args:?} failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn hard_cases_then_compile_then_hard_score() {
    let dir = tempfile::tempdir().unwrap();
    let hard = dir.path().join("hard");
    ok(&["hard-cases", "--out", s(&hard)]);
    let cases: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(hard.join("cases.json")).unwrap()).unwrap();
    assert_eq!(cases["cases"].as_array().unwrap().len(), 8);
    let case = hard.join("grazing");
    let pkg = dir.path().join("pkg");
    ok(&[
        "compile",
        s(&case.join("grazing.xml")),
        "--rays",
        s(&case.join("rays.txt")),
        "--reference",
        "double",
        "--out",
        s(&pkg),
    ]);
    let out = dir.path().join("score.json");
    let expect = case.join("expect.csv");
    ok(&[
        "hard-score",
        "--package",
        s(&pkg),
        "--hits",
        s(&pkg.join("reference.csv")),
        "--expect",
        s(&expect),
        "--out",
        s(&out),
    ]);
    let j: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let keys = [
        "case",
        "rays",
        "expect_hit",
        "expect_miss",
        "expect_any",
        "leaks",
        "false_hits",
        "wrong_prims",
        "flagged",
        "ok",
        "lists",
    ];
    assert_eq!(
        j.as_object()
            .unwrap()
            .keys()
            .collect::<std::collections::BTreeSet<_>>(),
        keys.iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .iter()
            .collect()
    );
    assert_eq!(
        (j["case"].as_str(), j["rays"].as_u64(), j["ok"].as_u64()),
        (Some("grazing"), Some(744), Some(744))
    );
    for l in ["leaks", "false_hits", "wrong_prims", "flagged"] {
        assert_eq!(j["lists"][l].as_array().map(Vec::len), Some(0), "{l}");
    }
    // A bad row is named by file and line.
    let text = std::fs::read_to_string(&expect)
        .unwrap()
        .replacen("2,hit", "2,hat", 1);
    std::fs::write(&expect, text).unwrap();
    let bad = bridge(&[
        "hard-score",
        "--package",
        s(&pkg),
        "--hits",
        s(&pkg.join("reference.csv")),
        "--expect",
        s(&expect),
        "--out",
        s(&out),
    ]);
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        !bad.status.success()
            && err.contains(&format!("{}:4:", expect.display()))
            && err.contains("'hat'"),
        "{err}"
    );
}
