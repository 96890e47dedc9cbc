//! `cargo run --release`: convex hulls of the same point clouds with parry3d 0.31.1 as
//! published (`orig`) and with gymfleet's patched copy (`new`, `../parry3d`). Every hull
//! must be identical, bit for bit (vertices and triangles), or the run fails; the wall
//! time of each is printed beside it.

use std::time::Instant;

/// A deterministic generator (xorshift64*), so that runs compare the same clouds.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32) / (1u64 << 24) as f32
    }
}

/// Named clouds: random in a cube (few hull points), on a sphere (all on the hull), a UV
/// sphere's vertices with their duplicates (an STL's), a box with points on its faces
/// (coplanar sets), and a fan (a coplanar rim and two apexes).
fn clouds() -> Vec<(String, Vec<[f32; 3]>)> {
    let mut out = Vec::new();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for n in [100usize, 10_000, 100_000] {
        let cube = (0..n).map(|_| [rng.next(), rng.next(), rng.next()]).collect();
        out.push((format!("cube/{n}"), cube));
    }
    for n in [100usize, 4_000, 20_000, 65_536] {
        let sphere = (0..n)
            .map(|_| {
                let v = [rng.next() - 0.5, rng.next() - 0.5, rng.next() - 0.5];
                let r = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-6);
                [v[0] / r, v[1] / r, v[2] / r]
            })
            .collect();
        out.push((format!("sphere/{n}"), sphere));
    }
    let (rings, segments) = (64usize, 128usize);
    let uv = |r: usize, s: usize| {
        let th = std::f32::consts::PI * r as f32 / rings as f32;
        let ph = 2.0 * std::f32::consts::PI * s as f32 / segments as f32;
        [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]
    };
    let mut stl = Vec::new();
    for r in 0..rings {
        for s in 0..segments {
            stl.extend([uv(r, s), uv(r + 1, s), uv(r + 1, s + 1)]);
            stl.extend([uv(r, s), uv(r + 1, s + 1), uv(r, s + 1)]);
        }
    }
    out.push((format!("uv_sphere_stl/{}", stl.len()), stl));
    let mut faces = Vec::new();
    for _ in 0..3_000 {
        let (a, b) = (rng.next(), rng.next());
        let side = (rng.next() * 6.0) as usize % 6;
        let p = match side {
            0 => [0.0, a, b],
            1 => [1.0, a, b],
            2 => [a, 0.0, b],
            3 => [a, 1.0, b],
            4 => [a, b, 0.0],
            _ => [a, b, 1.0],
        };
        faces.push(p);
    }
    out.push(("box_faces/3000".into(), faces));
    let n = 4_096usize;
    let mut fan = vec![[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
    fan.extend((0..n).map(|k| {
        let a = 2.0 * std::f32::consts::PI * k as f32 / n as f32;
        [a.cos(), a.sin(), 0.0]
    }));
    out.push((format!("fan/{}", fan.len()), fan));
    out
}

fn main() {
    let mut failed = false;
    for (name, cloud) in clouds() {
        let a: Vec<orig::math::Vector> = cloud
            .iter()
            .map(|p| orig::math::Vector::new(p[0], p[1], p[2]))
            .collect();
        let b: Vec<new::math::Vector> = cloud
            .iter()
            .map(|p| new::math::Vector::new(p[0], p[1], p[2]))
            .collect();
        let t = Instant::now();
        let ha = orig::transformation::try_convex_hull(&a);
        let ta = t.elapsed();
        let t = Instant::now();
        let hb = new::transformation::try_convex_hull(&b);
        let tb = t.elapsed();
        let same = match (&ha, &hb) {
            (Ok((va, ia)), Ok((vb, ib))) => {
                ia == ib
                    && va.len() == vb.len()
                    && va.iter().zip(vb).all(|(p, q)| {
                        [p.x, p.y, p.z].map(f32::to_bits) == [q.x, q.y, q.z].map(f32::to_bits)
                    })
            }
            (Err(ea), Err(eb)) => format!("{ea:?}") == format!("{eb:?}"),
            _ => false,
        };
        let hull = match &hb {
            Ok((v, i)) => format!("{} vertices, {} triangles", v.len(), i.len()),
            Err(e) => format!("error {e:?}"),
        };
        println!(
            "{name:>22}: {hull:>32}; published {:>9.2} ms, patched {:>9.2} ms; {}",
            ta.as_secs_f64() * 1e3,
            tb.as_secs_f64() * 1e3,
            if same { "identical" } else { "DIFFERENT" }
        );
        failed |= !same;
    }
    if failed {
        eprintln!("some hulls differ");
        std::process::exit(1);
    }
}
