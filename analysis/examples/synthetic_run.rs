//! A toy run to exercise `stripes analyze` and look at its plots without a DEM run: NOT
//! physics. 4000 grains (radii uniform in [0.25, 0.5] mm) start uniformly on the thesis
//! tray (0.4 m x 0.02 m) and, once per 20 Hz period for 20 s, each grain steps by up to
//! +-1 mm at random; from t = 2 s it also creeps 3 % of the way towards the nearest of five
//! centres, so five bands condense, and grains leave a band with a small probability.
//! Writes `OUT/snapshots.bin` (default OUT = out/synthetic-run).
//!
//!   cargo run --release -p analysis --example synthetic_run -- out/synthetic-run
//!   stripes analyze out/synthetic-run

use analysis::snapshot::{Header, SnapshotWriter};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() -> std::io::Result<()> {
    let out = std::path::PathBuf::from(std::env::args().nth(1).unwrap_or_else(|| "out/synthetic-run".into()));
    std::fs::create_dir_all(&out)?;
    let (n, l, w, period, frames) = (4000, 0.4, 0.02, 0.05, 401);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let radii: Vec<f64> = (0..n).map(|_| rng.gen_range(2.5e-4..5e-4)).collect();
    let mut pos: Vec<[f64; 3]> = radii.iter().map(|&r| [rng.gen_range(0.0..l), rng.gen_range(r..w - r), r]).collect();
    let centres = [0.03, 0.11, 0.2, 0.27, 0.35];
    let mut writer = SnapshotWriter::create(
        &out.join("snapshots.bin"),
        Header {
            length: l,
            width: w,
            radii,
        },
    )?;
    for f in 0..frames {
        let t = f as f64 * period;
        let vel: Vec<[f64; 3]> = pos.iter().map(|_| [rng.gen_range(-0.02..0.02), 0.0, 0.0]).collect();
        writer.push(t, pos.iter().copied(), vel.into_iter())?;
        for p in pos.iter_mut() {
            let mut x = p[0] + rng.gen_range(-1e-3..1e-3);
            if t >= 2.0 && rng.gen_range(0.0..1.0) > 0.002 {
                let (d, _) = centres
                    .iter()
                    .map(|c| {
                        let d = c - x;
                        (d - l * (d / l).round(), 0)
                    })
                    .min_by(|a, b| a.0.abs().total_cmp(&b.0.abs()))
                    .expect("five centres");
                x += 0.03 * d;
            }
            p[0] = x.rem_euclid(l);
            p[1] = (p[1] + rng.gen_range(-2e-4..2e-4)).clamp(p[2], w - p[2]);
        }
    }
    writer.sync()?;
    println!("{}", out.join("snapshots.bin").display());
    Ok(())
}
