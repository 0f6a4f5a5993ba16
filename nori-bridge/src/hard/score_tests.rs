use super::*;

fn hit(prim: i64) -> Hit {
    Hit {
        hit: true,
        t: 1.0,
        u: 0.25,
        v: 0.25,
        prim,
        error: 0,
    }
}

#[test]
fn each_class_is_counted_once() {
    let ex = vec![
        Expected::Hit(vec![1, 2]), // 0: hit prim 2 -> ok
        Expected::Hit(vec![]),     // 1: miss -> leak
        Expected::Miss,            // 2: hit -> false hit
        Expected::Any,             // 3: miss -> ok
        Expected::Hit(vec![1]),    // 4: hit prim 3 -> wrong prim
        Expected::Hit(vec![5]),    // 5: error flag -> flagged (not a leak)
        Expected::Miss,            // 6: miss with error flag -> flagged (not ok)
        Expected::Any,             // 7: hit -> ok
        Expected::Hit(vec![]),     // 8: any prim -> ok
    ];
    let hits = vec![
        hit(2),
        Hit::MISS,
        hit(0),
        Hit::MISS,
        hit(3),
        Hit {
            error: 4,
            ..Hit::MISS
        },
        Hit {
            error: 1,
            ..Hit::MISS
        },
        hit(9),
        hit(7),
    ];
    let s = score("t", &ex, &hits);
    let want = Score {
        case: "t".into(),
        rays: 9,
        expect_hit: 5,
        expect_miss: 2,
        expect_any: 2,
        leaks: 1,
        false_hits: 1,
        wrong_prims: 1,
        flagged: 2,
        ok: 4,
        lists: Lists {
            leaks: vec![1],
            false_hits: vec![2],
            wrong_prims: vec![4],
            flagged: vec![5, 6],
        },
    };
    assert_eq!(s, want);
}

#[test]
fn lists_are_capped_counts_are_not() {
    let ex = vec![Expected::Hit(vec![]); 1500];
    let s = score("t", &ex, &vec![Hit::MISS; 1500]);
    assert_eq!(
        (s.leaks, s.lists.leaks.len(), s.lists.leaks[999]),
        (1500, 1000, 999)
    );
}

fn expect_err(body: &str, line: usize, value: &str) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("expect.csv");
    std::fs::write(&p, body).unwrap();
    let e = format!("{:#}", read_expect(&p).unwrap_err());
    assert!(
        e.contains(&format!("{}:{line}:", p.display())) && e.contains(value),
        "{body:?} gave: {e}"
    );
}

#[test]
fn malformed_expect_is_rejected_with_file_and_line() {
    expect_err("ray,hit,prims\n0,hit,\n", 1, "ray,hit,prims");
    expect_err("ray,expect,prims\n0,hit,1;2\n1,maybe,\n", 3, "maybe");
    expect_err("ray,expect,prims\n0,hit,1;x\n", 2, "'x'");
    expect_err("ray,expect,prims\n0,hit,-3\n", 2, "'-3'");
    expect_err("ray,expect,prims\n0,miss,4\n", 2, "'4'");
    expect_err("ray,expect,prims\n0,any,\n2,hit,\n", 3, "'2'");
    expect_err("ray,expect,prims\n0,hit\n", 2, "2 columns");
}

#[test]
fn well_formed_expect_reads_back() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("expect.csv");
    std::fs::write(&p, "ray,expect,prims\n0,hit,3;4\n1,miss,\n2,any,\n3,hit,\n").unwrap();
    assert_eq!(
        read_expect(&p).unwrap(),
        vec![
            Expected::Hit(vec![3, 4]),
            Expected::Miss,
            Expected::Any,
            Expected::Hit(vec![])
        ]
    );
}
