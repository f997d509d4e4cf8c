//! The cache of prepared samples: `sample-<key>.bin` files in a directory shared by all runs
//! (key: [`sample_key`]). The physics crate prepares a sample; this module names, stores and
//! loads it.

use particles::prepare::{prepare, reference, SAMPLE_REVISION};
use particles::scene::Scene;
use particles::state::State;
use particles::Vec3;

use crate::rundir::bytes::{seal, unseal, Reader, Writer};

/// A stable 64-bit name of the sample a scene starts from: FNV-1a of
/// [`SAMPLE_REVISION`] and the canonical TOML of the scene's
/// [`particles::prepare::reference`], which holds the seed.
pub fn sample_key(scene: &Scene) -> u64 {
    sample_key_at(scene, SAMPLE_REVISION)
}

/// [`sample_key`] as a version of sample revision `revision` named the scene's sample.
pub fn sample_key_at(scene: &Scene, revision: u64) -> u64 {
    let text = toml::to_string(&reference(scene)).expect("a scene serialises");
    particles::measure::fnv1a(format!("sample revision {revision}\n{text}").as_bytes())
}

/// The grains' fixed properties (radii, masses, inertias) for a run that continues from a
/// checkpoint, which holds every moving quantity: the lattice before relaxation (a
/// relaxation moves grains, it never changes their radii or masses), through the cache's
/// encoding, so that they are the bits a prepared sample gives. A resume neither prepares
/// the sample (for the thesis scene, 10 s of relaxation) nor needs it in the cache.
pub fn for_resume(scene: &Scene) -> Result<State, String> {
    let lattice = particles::prepare::initial_state(scene).map_err(|e| format!("sample: {e}"))?;
    decode_sample(&encode_sample(&lattice))
}

/// Loads the sample of `scene` from `dir` (file `sample-<key>.bin`, see [`sample_key`]) or
/// prepares and stores it. Returns the state and whether it came from the cache.
pub fn load_or_prepare(scene: &Scene, dir: &std::path::Path, progress: impl FnMut(f64)) -> Result<(State, bool), String> {
    let key = sample_key(scene);
    let path = dir.join(format!("sample-{key:016x}.bin"));
    // Jobs of a sweep running in parallel threads often need the same sample: one prepares
    // it while the others wait for it, then load it from the cache.
    static BUSY: std::sync::Mutex<Vec<(u64, std::sync::Arc<std::sync::Mutex<()>>)>> = std::sync::Mutex::new(Vec::new());
    let lock = {
        let mut busy = BUSY.lock().unwrap_or_else(|e| e.into_inner());
        match busy.iter().find(|(k, _)| *k == key) {
            Some((_, l)) => l.clone(),
            None => {
                let l = std::sync::Arc::new(std::sync::Mutex::new(()));
                busy.push((key, l.clone()));
                l
            }
        }
    };
    let _guard = lock.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(state) = load(&path)? {
        return Ok((state, true));
    }
    // Jobs in other processes (shards, concurrent runs) wait on a lock file instead.
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let _file_lock = match FileLock::acquire(&dir.join(format!("sample-{key:016x}.lock")), &path)? {
        Some(l) => l,
        None => {
            let state = load(&path)?.ok_or_else(|| format!("{}: the process preparing it stopped without writing it", path.display()))?;
            return Ok((state, true));
        }
    };
    if let Some(state) = load(&path)? {
        return Ok((state, true));
    }
    let state = prepare(scene, progress).map_err(|e| format!("sample preparation: {e}"))?;
    let bytes = encode_sample(&state);
    analysis::io::write_atomic(&path, &bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    // Return what a later run will load, bit for bit (the stored mass gives back the inverse
    // mass only to within an ulp), so a fresh and a cached sample run identically.
    Ok((decode_sample(&bytes).expect("a sample just encoded decodes"), false))
}

/// The sample at `path`, if it is there.
fn load(path: &std::path::Path) -> Result<Option<State>, String> {
    match std::fs::read(path) {
        Ok(bytes) => decode_sample(&bytes).map(Some).map_err(|e| format!("{}: {e}", path.display())),
        Err(_) => Ok(None),
    }
}

/// How often a process waiting for another's sample looks again.
const LOCK_POLL: std::time::Duration = std::time::Duration::from_millis(100);

/// A lock file `sample-<key>.lock` holding the preparing process' id: created with
/// `create_new`, so exactly one process prepares a sample; removed when dropped. A lock
/// whose process is gone (killed during preparation) is taken over.
struct FileLock(std::path::PathBuf);

impl FileLock {
    /// Takes the lock, or waits until the sample `product` exists (then `None`: load it).
    fn acquire(lock: &std::path::Path, product: &std::path::Path) -> Result<Option<Self>, String> {
        use std::io::Write as _;
        loop {
            match std::fs::OpenOptions::new().write(true).create_new(true).open(lock) {
                Ok(mut f) => {
                    let _ = write!(f, "{}", std::process::id());
                    return Ok(Some(Self(lock.to_path_buf())));
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    if product.exists() {
                        return Ok(None);
                    }
                    let owner = std::fs::read_to_string(lock).ok().and_then(|t| t.trim().parse::<u32>().ok());
                    // A lock of a process that no longer runs is stale (Linux: /proc/<pid>).
                    let alive =
                        owner.is_none_or(|pid| std::path::Path::new(&format!("/proc/{pid}")).exists() || !cfg!(target_os = "linux"));
                    if !alive {
                        let _ = std::fs::remove_file(lock);
                        continue;
                    }
                    std::thread::sleep(LOCK_POLL);
                }
                Err(e) => return Err(format!("cannot create the lock {}: {e}", lock.display())),
            }
        }
    }
}

impl Drop for FileLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

const SAMPLE_MAGIC: &[u8; 8] = b"STRPSMP2";
/// The same layout without the checksum.
const SAMPLE_MAGIC_UNSEALED: &[u8; 8] = b"STRPSMP1";

/// Binary sample: magic, `u64` N, then per grain position (3 `f64`), radius, mass, then the
/// FNV-1a of every byte after the magic ([`crate::rundir::bytes::seal`]).
fn encode_sample(s: &State) -> Vec<u8> {
    let mut w = Writer::default();
    w.0.extend_from_slice(SAMPLE_MAGIC);
    w.u64(s.len() as u64);
    for i in 0..s.len() {
        w.vec3(&s.pos[i]);
        w.f64(s.radius[i]);
        w.f64(s.mass(i));
    }
    seal(&mut w.0, SAMPLE_MAGIC.len());
    w.0
}

fn decode_sample(bytes: &[u8]) -> Result<State, String> {
    let bytes = match bytes.get(..8) {
        Some(m) if m == SAMPLE_MAGIC => unseal(bytes, SAMPLE_MAGIC.len())?,
        Some(m) if m == SAMPLE_MAGIC_UNSEALED => bytes,
        _ => return Err("not a stripes sample file".into()),
    };
    if bytes.len() < 16 {
        return Err("not a stripes sample file".into());
    }
    let mut r = Reader::new(&bytes[8..]);
    let n = r.count(5 * 8, "grains")?;
    let mut s = State::default();
    for _ in 0..n {
        let (pos, radius, mass) = (r.vec3()?, r.f64()?, r.f64()?);
        s.push(pos, Vec3::zeros(), Vec3::zeros(), radius, mass);
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresh_sample_equals_cached_sample_bit_for_bit() {
        // Regression: the in-memory sample of the run that prepared it differed from the
        // cached file by an ulp in the inverse mass, so that first run did not reproduce.
        let text = r#"
            [box]
            length = 0.01
            width = 0.005
            [drive]
            frequency = 20.0
            amplitude = 0.025
            [particles]
            count = 20
            radius_min = 0.25e-3
            radius_max = 0.5e-3
            [prepare]
            duration = 0.01
            [run]
            duration = 0.1
            dt = 8e-6
            seed = 3
        "#;
        let scene = crate::scene::text::parse_scene(text, &[], "test").unwrap();
        let dir = std::env::temp_dir().join(format!("stripes-sample-{}", std::process::id()));
        let (fresh, cached) = load_or_prepare(&scene, &dir, |_| ()).unwrap();
        assert!(!cached);
        let (again, cached) = load_or_prepare(&scene, &dir, |_| ()).unwrap();
        assert!(cached);
        assert_eq!(fresh, again);
        std::fs::remove_dir_all(dir).unwrap();
    }
}
