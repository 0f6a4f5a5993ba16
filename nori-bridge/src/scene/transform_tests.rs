//! Transforms against hand-computed matrices.

use super::*;

fn close(a: &Mat4, b: &[f64; 16]) {
    for i in 0..4 {
        for j in 0..4 {
            assert!(
                (a.m[i][j] - b[i * 4 + j]).abs() < 1e-12,
                "m[{i}][{j}] = {} expected {}\n{a:?}",
                a.m[i][j],
                b[i * 4 + j]
            );
        }
    }
}

#[test]
fn translate_scale_matrix_rows() {
    close(
        &Mat4::translate([1.0, 2.0, 3.0]),
        &[
            1., 0., 0., 1., 0., 1., 0., 2., 0., 0., 1., 3., 0., 0., 0., 1.,
        ],
    );
    close(
        &Mat4::scale([2.0, 3.0, 4.0]),
        &[
            2., 0., 0., 0., 0., 3., 0., 0., 0., 0., 4., 0., 0., 0., 0., 1.,
        ],
    );
    let v: [f64; 16] = std::array::from_fn(|i| i as f64);
    close(&Mat4::from_rows(&v), &v);
}

#[test]
fn rotate_90_about_z_maps_x_to_y() {
    close(
        &Mat4::rotate([0.0, 0.0, 1.0], 90.0),
        &[
            0., -1., 0., 0., 1., 0., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.,
        ],
    );
    // A non-unit axis is normalised: same rotation.
    close(
        &Mat4::rotate([0.0, 0.0, 5.0], 90.0),
        &[
            0., -1., 0., 0., 1., 0., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.,
        ],
    );
    // 120 degrees about (1,1,1) permutes the axes x -> y -> z -> x.
    close(
        &Mat4::rotate([1.0, 1.0, 1.0], 120.0),
        &[
            0., 0., 1., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 0., 1.,
        ],
    );
}

#[test]
fn lookat_columns_are_left_up_dir_origin() {
    // Looking from (0,0,-5) to the origin with up +y: dir = +z,
    // left = up x dir = +x, newUp = dir x left = +y.
    close(
        &Mat4::lookat([0.0, 0.0, -5.0], [0.0; 3], [0.0, 1.0, 0.0]),
        &[
            1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., -5., 0., 0., 0., 1.,
        ],
    );
    // Looking down -y from (1,2,3) with up +z: dir = -y, left = z x -y = +x,
    // newUp = -y x x = +z.
    close(
        &Mat4::lookat([1.0, 2.0, 3.0], [1.0, 0.0, 3.0], [0.0, 0.0, 1.0]),
        &[
            1., 0., 0., 1., 0., 0., -1., 2., 0., 1., 0., 3., 0., 0., 0., 1.,
        ],
    );
}

#[test]
fn composition_applies_first_child_first() {
    // <scale 2/> then <translate 1,0,0/>: M = T * S, so (1,0,0) -> (3,0,0).
    let m = Mat4::translate([1.0, 0.0, 0.0]).mul(&Mat4::scale([2.0, 2.0, 2.0]));
    assert_eq!(m.point([1.0, 0.0, 0.0]), [3.0, 0.0, 0.0]);
    assert_eq!(m.vector([1.0, 0.0, 0.0]), [2.0, 0.0, 0.0]);
}

#[test]
fn number_lists_accept_commas_and_spaces() {
    assert_eq!(parse_floats("1, 2 3,4").unwrap(), vec![1.0, 2.0, 3.0, 4.0]);
    assert_eq!(parse_vec3(" -1,2.5 ,1e3 ").unwrap(), [-1.0, 2.5, 1000.0]);
    let e = parse_vec3("1, 2").unwrap_err();
    assert!(e.contains("expected 3 numbers, got 2"), "{e}");
    let e = parse_vec3("1, x, 2").unwrap_err();
    assert!(e.contains("'x'"), "{e}");
}
