//! How each soma trunk starts (developer tool): `trunk_plan FILE.swc`.
//! Per trunk: the first two samples' distance from the soma centre and radii,
//! where its tube starts, and whether the soma joins it or it is spliced.
use glam::DVec3;

fn main() {
    let path = std::env::args().nth(1).expect("swc");
    let m = neuromesh::Morphology::from_swc(&path).expect("swc");
    let params = neuromesh::Params::default();
    let branches = neuromesh::skeleton::branch::identify(&m, params.angle_threshold);
    let geometry = neuromesh::skeleton::geometry::Geometry::new(&m, &params);
    let tracks = neuromesh::skeleton::tracks(
        &geometry,
        &branches,
        &params,
        neuromesh::skeleton::track::SWEEP_CAP,
    );
    let starts = neuromesh::build::plan::plan(&m, &geometry, &branches, &tracks, &params);
    for plan in &starts.somas {
        let c = plan.sphere.center;
        println!(
            "soma r {:.3} spacing {:.3}",
            plan.sphere.radius, plan.spacing
        );
        for (i, b) in branches.iter().enumerate() {
            if !matches!(
                b.attachment,
                neuromesh::skeleton::branch::Attachment::Soma { .. }
            ) {
                continue;
            }
            let t = &tracks[i];
            let s1 = b.samples[1] as usize;
            let d1 = DVec3::from_array(m.positions()[s1]).distance(c);
            let how = if plan.trunks.contains(&(i as u32)) {
                "soma"
            } else if starts.spliced_trunk[i].is_some() {
                "spliced"
            } else {
                "hidden/other"
            };
            match starts.start[i] {
                Some(k) => println!(
                    "  line {:6} first sample d {d1:8.3} r {:6.3} | start k {k:3} d {:8.3} r {:6.3} m {:3} cos {:+.2} {how} filler {:?}",
                    m.lines()[s1],
                    m.radii()[s1],
                    t.samples[k].pos.distance(c),
                    t.radii[k],
                    t.counts[k],
                    t.samples[k]
                        .tangent
                        .dot((t.samples[k].pos - c).normalize_or_zero()),
                    starts.filler[i],
                ),
                None => println!("  line {:6} hidden", m.lines()[s1]),
            }
        }
    }
}
