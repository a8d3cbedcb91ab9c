//! Times the phases of reading and checking a mesh file (developer tool).
use std::time::Instant;
fn main() {
    let path = std::env::args().nth(1).expect("mesh file");
    let t = Instant::now();
    let mesh = neuromesh::io::read(&path).expect("read");
    println!(
        "read {:.0} ms ({} faces)",
        t.elapsed().as_secs_f64() * 1e3,
        mesh.faces.len()
    );
    let t = Instant::now();
    let _ = mesh.area() + mesh.volume();
    println!("area+volume {:.0} ms", t.elapsed().as_secs_f64() * 1e3);
    let t = Instant::now();
    let pairs = neuromesh::internals::measure::check::self_intersections(&mesh.view());
    println!(
        "self-intersections {:.0} ms ({} pairs)",
        t.elapsed().as_secs_f64() * 1e3,
        pairs.len()
    );
    let t = Instant::now();
    let r = mesh.check();
    println!(
        "full check {:.0} ms (closed {})",
        t.elapsed().as_secs_f64() * 1e3,
        r.is_closed()
    );
}
