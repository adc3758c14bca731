//! `indicatrix_peer`: renders one pass of a faceted stone with the `indicatrix` crate's
//! spectral, polarized CPU path tracer (its public API: `renderer::cpu_frame::
//! trace_pixels_interleaved` over a `renderer::frame_scene::FrameScene`), for
//! `scripts/bench/bench_fire.py`.
//!
//! Usage:
//!     indicatrix_peer SCENE.txt --spp N --offset K --out PASS.pfm [--threads T]
//!     indicatrix_peer SCENE.txt --calibrate
//!     indicatrix_peer --spectrum R G B
//!
//! `SCENE.txt` (written by bench_fire.py, already in indicatrix's y-up frame), one item a line:
//!     width W / height H / max_bounces B / material NAME
//!     index N           (optional: replace the material's dispersion by the constant index N)
//!     camera ox oy oz  fx fy fz  rx ry rz  ux uy uz  fov_tan   (origin, unit forward/right/up)
//!     env PATH.pfm      (lat-long RGB map in indicatrix's layout, a PFM file, top row = zenith)
//!     plane nx ny nz d  (one per facet: n . x + d <= 0 inside, n the outward unit normal)
//!
//! Writes the mean CIE XYZ per pixel of samples `K .. K + N` (a pixel's sample stream depends
//! on (pixel, sample index) only, so disjoint offsets are independent passes) as a 3-channel
//! PFM, and prints `seconds S` (wall time of the trace, not of loading).  `--calibrate`
//! prints the XYZ that a white (1, 1, 1) texel seen directly produces (the scale that maps
//! indicatrix's XYZ to warpoptics', whose white texel has Y = 1).  `--spectrum R G B` prints
//! the spectral radiance indicatrix gives a map texel of linear RGB (R, G, B), 360-830 nm at 1 nm
//! (`renderer::env_map::rgb_to_spectral_radiance`), one `wavelength value` pair a line.
//!
//! Threads: the pixels are split into interleaved partitions (`first_pixel = t, stride = T`),
//! one per thread, as indicatrix's own desktop front end does; the sums do not depend on T.

use std::io::{Read, Write};
use std::time::Instant;

use glam::Vec3;
use indicatrix::geometry::GpuFacetPlane;
use indicatrix::optics::dispersion::DispersionModel;
use indicatrix::optics::materials::GemMaterial;
use indicatrix::optics::raytracer::{Camera, EnvironmentSource};
use indicatrix::renderer::cpu_frame::{scatter_interleaved, trace_pixels_interleaved};
use indicatrix::renderer::env_map::{EnvironmentMap, rgb_to_spectral_radiance};
use indicatrix::renderer::frame_scene::FrameScene;
use indicatrix::simd::PlanesSoA32;

struct Scene {
    width: u32,
    height: u32,
    max_bounces: u32,
    material: String,
    index: Option<f32>,
    camera: [f32; 13],
    env: String,
    planes: Vec<GpuFacetPlane>,
}

fn fail(msg: &str) -> ! {
    eprintln!("indicatrix_peer: {msg}");
    std::process::exit(2);
}

fn floats(words: &[&str], n: usize, what: &str) -> Vec<f32> {
    if words.len() != n {
        fail(&format!("{what}: expected {n} numbers, got {}", words.len()));
    }
    words
        .iter()
        .map(|w| w.parse::<f32>().unwrap_or_else(|_| fail(&format!("{what}: not a number: {w}"))))
        .collect()
}

fn read_scene(path: &str) -> Scene {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| fail(&format!("{path}: {e}")));
    let mut s = Scene {
        width: 0,
        height: 0,
        max_bounces: 16,
        material: "Diamond".into(),
        index: None,
        camera: [0.0; 13],
        env: String::new(),
        planes: Vec::new(),
    };
    for line in text.lines() {
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some((key, rest)) = words.split_first() else { continue };
        match *key {
            "width" => s.width = floats(rest, 1, key)[0] as u32,
            "height" => s.height = floats(rest, 1, key)[0] as u32,
            "max_bounces" => s.max_bounces = floats(rest, 1, key)[0] as u32,
            "material" => s.material = rest.join(" "),
            "index" => s.index = Some(floats(rest, 1, key)[0]),
            "camera" => s.camera.copy_from_slice(&floats(rest, 13, key)),
            "env" => s.env = rest.join(" "),
            "plane" => {
                let v = floats(rest, 4, key);
                s.planes.push(GpuFacetPlane::new(Vec3::new(v[0], v[1], v[2]), v[3]));
            }
            k if k.starts_with('#') => {}
            k => fail(&format!("{path}: unknown key {k}")),
        }
    }
    if s.width == 0 || s.height == 0 || s.planes.len() < 4 || s.env.is_empty() {
        fail(&format!("{path}: needs width, height, env and at least 4 planes"));
    }
    s
}

/// A little-endian 3-channel PFM (rows bottom to top on disk) as top-to-bottom RGB texels.
fn read_pfm(path: &str) -> (usize, usize, Vec<[f32; 3]>) {
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|mut f| f.read_to_end(&mut bytes))
        .unwrap_or_else(|e| fail(&format!("{path}: {e}")));
    let mut fields = Vec::new();
    let mut pos = 0;
    while fields.len() < 4 {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        fields.push(String::from_utf8_lossy(&bytes[start..pos]).into_owned());
    }
    pos += 1; // the single whitespace byte after the scale
    let (w, h): (usize, usize) = (
        fields[1].parse().unwrap_or_else(|_| fail("pfm width")),
        fields[2].parse().unwrap_or_else(|_| fail("pfm height")),
    );
    if fields[0] != "PF" || !fields[3].starts_with('-') || bytes.len() < pos + w * h * 12 {
        fail(&format!("{path}: not a little-endian RGB PFM of {w}x{h}"));
    }
    let mut texels = vec![[0.0f32; 3]; w * h];
    for row in 0..h {
        for col in 0..w {
            let o = pos + ((h - 1 - row) * w + col) * 12;
            let f = |k: usize| f32::from_le_bytes(bytes[o + 4 * k..o + 4 * k + 4].try_into().unwrap());
            texels[row * w + col] = [f(0), f(1), f(2)];
        }
    }
    (w, h, texels)
}

fn write_pfm(path: &str, w: u32, h: u32, xyz: &[Vec3]) {
    let mut out = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    for row in (0..h).rev() {
        for col in 0..w {
            let v = xyz[(row * w + col) as usize];
            for c in [v.x, v.y, v.z] {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    let tmp = format!("{path}.tmp");
    std::fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(&out))
        .and_then(|()| std::fs::rename(&tmp, path))
        .unwrap_or_else(|e| fail(&format!("{path}: {e}")));
}

/// Mean XYZ per pixel of samples `offset .. offset + spp`, traced on `threads` threads.
fn render(frame: &FrameScene<'_>, offset: u32, spp: u32, threads: u32) -> Vec<Vec3> {
    let soa = PlanesSoA32::from_normals_d(frame.planes.iter().map(|p| (p.normal, p.d)), frame.planes.len());
    let n = (frame.width * frame.height) as usize;
    let mut sums = vec![Vec3::ZERO; n];
    let parts: Vec<Vec<Vec3>> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let soa = &soa;
                scope.spawn(move || trace_pixels_interleaved(frame, soa, t, threads, offset, spp))
            })
            .collect();
        handles.into_iter().map(|h| h.join().expect("a tracing thread panicked")).collect()
    });
    for (t, part) in parts.iter().enumerate() {
        scatter_interleaved(&mut sums, t as u32, threads, part);
    }
    let inv = 1.0 / spp as f32;
    sums.iter().map(|s| *s * inv).collect()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 5 && args[1] == "--spectrum" {
        let rgb: Vec<f32> = args[2..5].iter().map(|a| a.parse().unwrap_or_else(|_| fail("--spectrum R G B"))).collect();
        for nm in 360..=830 {
            println!("{nm} {}", rgb_to_spectral_radiance([rgb[0], rgb[1], rgb[2]], nm as f32));
        }
        return;
    }
    if args.len() < 2 {
        fail("usage: indicatrix_peer SCENE.txt (--spp N --offset K --out PASS.pfm [--threads T] | --calibrate)");
    }
    let mut spp = 1u32;
    let mut offset = 0u32;
    let mut out = String::new();
    let mut calibrate = false;
    let mut threads = std::thread::available_parallelism().map_or(1, |n| n.get() as u32);
    let mut i = 2;
    while i < args.len() {
        let val = || args.get(i + 1).cloned().unwrap_or_else(|| fail(&format!("{} needs a value", args[i])));
        match args[i].as_str() {
            "--spp" => spp = val().parse().unwrap_or_else(|_| fail("--spp")),
            "--offset" => offset = val().parse().unwrap_or_else(|_| fail("--offset")),
            "--threads" => threads = val().parse().unwrap_or_else(|_| fail("--threads")),
            "--out" => out = val(),
            "--calibrate" => {
                calibrate = true;
                i -= 1;
            }
            a => fail(&format!("unknown argument {a}")),
        }
        i += 2;
    }
    let scene = read_scene(&args[1]);
    let mut material = GemMaterial::by_name(&scene.material)
        .unwrap_or_else(|| fail(&format!("no built-in material {}", scene.material)));
    if let Some(n) = scene.index {
        material.dispersion = DispersionModel::Cauchy { a: n, b: 0.0, c: 0.0 };
    }
    let c = scene.camera;
    let camera = Camera {
        origin: Vec3::new(c[0], c[1], c[2]),
        forward: Vec3::new(c[3], c[4], c[5]),
        right: Vec3::new(c[6], c[7], c[8]),
        up: Vec3::new(c[9], c[10], c[11]),
        fov_tan: c[12],
    };
    if calibrate {
        // A uniform white map seen straight away from the stone: every ray misses it.
        let white = EnvironmentMap::uniform(8, 4, [1.0, 1.0, 1.0]);
        let away = Camera { forward: -camera.forward, right: -camera.right, ..camera };
        let frame = FrameScene {
            camera: &away,
            width: 4,
            height: 4,
            planes: &scene.planes,
            facet_finishes: &[],
            material: &material,
            max_bounces: scene.max_bounces,
            environment: EnvironmentSource::HdrMap(&white),
        };
        let xyz = render(&frame, 0, 256, 1);
        let mean = xyz.iter().fold(Vec3::ZERO, |a, b| a + *b) / xyz.len() as f32;
        println!("white_xyz {} {} {}", mean.x, mean.y, mean.z);
        return;
    }
    if out.is_empty() {
        fail("--out PASS.pfm is required");
    }
    let (w, h, texels) = read_pfm(&scene.env);
    let env = EnvironmentMap::from_rgb(w, h, texels).unwrap_or_else(|e| fail(&e.to_string()));
    let frame = FrameScene {
        camera: &camera,
        width: scene.width,
        height: scene.height,
        planes: &scene.planes,
        facet_finishes: &[],
        material: &material,
        max_bounces: scene.max_bounces,
        environment: EnvironmentSource::HdrMap(&env),
    };
    let t0 = Instant::now();
    let xyz = render(&frame, offset, spp, threads.max(1));
    let seconds = t0.elapsed().as_secs_f64();
    write_pfm(&out, scene.width, scene.height, &xyz);
    println!("seconds {seconds}");
    println!("threads {threads}");
}
