//! Area and volume errors of simple tubes against their analytic values (developer tool).
use neuromesh::{Morphology, Params};
fn main() {
    let pi = std::f64::consts::PI;
    for minv in [8u32, 10, 12, 16] {
        let p = Params::default().with_min_vertices(minv);
        // cylinder r=1 length 20 as 3 points, capsule reference
        let ids = [1i64, 2, 3];
        let m = Morphology::from_arrays(
            &ids,
            &[3, 3, 3],
            &[[0.0; 3], [10.0, 0.0, 0.0], [20.0, 0.0, 0.0]],
            &[1.0; 3],
            &[-1, 1, 2],
        )
        .unwrap();
        let mesh = neuromesh::mesh_morphology(&m, &p).unwrap();
        let (a, v) = (2.0 * pi * 20.0 + 4.0 * pi, pi * 20.0 + 4.0 / 3.0 * pi);
        println!(
            "min {minv} cylinder: area {:+.3}% vol {:+.3}% tris {}",
            100.0 * (mesh.area() / a - 1.0),
            100.0 * (mesh.volume() / v - 1.0),
            mesh.faces.len()
        );
        // cone r 2 -> 1 over 20
        let m = Morphology::from_arrays(
            &ids,
            &[3, 3, 3],
            &[[0.0; 3], [10.0, 0.0, 0.0], [20.0, 0.0, 0.0]],
            &[2.0, 1.5, 1.0],
            &[-1, 1, 2],
        )
        .unwrap();
        let mesh = neuromesh::mesh_morphology(&m, &p).unwrap();
        // round cone union: frustum tangent to spheres + sphere caps; compute exactly
        let (r1, r2, l) = (2.0f64, 1.0f64, 20.0f64);
        let s = (r1 - r2) / l; // sin of half angle
        let c = (1.0 - s * s).sqrt();
        let (h1, h2) = (r1 * s, r2 * s); // offsets of tangent circles along axis (toward smaller)
        let (a1, a2) = (r1 * c, r2 * c); // tangent circle radii
        let len = l - h1 + h2; // axial length between tangent circles
        let slant = ((a1 - a2).powi(2) + len * len).sqrt();
        let lateral = pi * (a1 + a2) * slant;
        let cap1 = 2.0 * pi * r1 * (r1 + h1); // big sphere cap beyond tangent circle (away side)
        let cap2 = 2.0 * pi * r2 * (r2 - h2);
        let frustum_v = pi * len / 3.0 * (a1 * a1 + a1 * a2 + a2 * a2);
        let capv = |r: f64, h: f64| pi * h * h * (3.0 * r - h) / 3.0;
        let v1 = capv(r1, r1 + h1);
        let v2 = capv(r2, r2 - h2);
        let (a, v) = (lateral + cap1 + cap2, frustum_v + v1 + v2);
        println!(
            "min {minv} cone:     area {:+.3}% vol {:+.3}% tris {}",
            100.0 * (mesh.area() / a - 1.0),
            100.0 * (mesh.volume() / v - 1.0),
            mesh.faces.len()
        );
    }
}
#[allow(dead_code)]
fn bent() {}
