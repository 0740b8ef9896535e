//! Seeded 2D value noise and its fractal sum (fBm) for procedural terrain. Value noise
//! rather than gradient noise because the terrain only needs gentle rolling hills: random
//! heights on an integer lattice, blended with a quintic fade so that the surface (and so
//! the normals the blades grow along) has no creases at the lattice lines.
//!
//! The noise is the CPU twin of `shaders/terrain_height.wgsl`, which evaluates the same
//! function in the terrain's vertex shader: so the lattice hash is a 32-bit integer hash
//! (WGSL has no 64-bit integers), lattice coordinates are `i32`, and a lattice value has
//! 24 bits, exact in `f32`. The 64-bit scene seed is folded into one 32-bit seed per
//! octave here on the CPU ([`octave_seeds`]) and handed to the GPU as such.

use super::rng::mix64;

/// Lacunarity of the fBm: each octave doubles the frequency ...
const LACUNARITY: f64 = 2.0;
/// ... and halves the amplitude.
const GAIN: f64 = 0.5;

/// A 32-bit integer hash (the PCG output permutation of Jarzynski & Olano 2020, "Hash
/// Functions for GPU Rendering"): cheap on a GPU and well mixed in every bit.
pub fn hash32(x: u32) -> u32 {
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The pseudo-random value in `[-1, 1]` at lattice point `(ix, iz)`.
fn lattice(seed: u32, ix: i32, iz: i32) -> f64 {
    let h = hash32(seed ^ hash32((ix as u32) ^ hash32(iz as u32).rotate_left(17)));
    f64::from(h >> 8) * (2.0 / f64::from(1u32 << 24)) - 1.0
}

/// Quintic fade 6t⁵ − 15t⁴ + 10t³: zero first and second derivatives at 0 and 1.
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Derivative of [`fade`]: 30t²(t − 1)².
fn fade_derivative(t: f64) -> f64 {
    30.0 * t * t * (t - 1.0) * (t - 1.0)
}

/// Value noise in `[-1, 1]` with unit lattice spacing and its gradient `(∂/∂x, ∂/∂z)`.
fn value_noise_grad(seed: u32, x: f64, z: f64) -> (f64, f64, f64) {
    let (x0, z0) = (x.floor(), z.floor());
    let (ix, iz) = (x0 as i64 as i32, z0 as i64 as i32);
    let (fx, fz) = (x - x0, z - z0);
    let (tx, tz) = (fade(fx), fade(fz));
    let a = lattice(seed, ix, iz);
    let b = lattice(seed, ix.wrapping_add(1), iz);
    let c = lattice(seed, ix, iz.wrapping_add(1));
    let d = lattice(seed, ix.wrapping_add(1), iz.wrapping_add(1));
    let top = a + (b - a) * tx;
    let bottom = c + (d - c) * tx;
    let value = top + (bottom - top) * tz;
    let dx = ((b - a) + (a - b - c + d) * tz) * fade_derivative(fx);
    let dz = (bottom - top) * fade_derivative(fz);
    (value, dx, dz)
}

/// Value noise in `[-1, 1]` with unit lattice spacing.
pub fn value_noise(seed: u64, x: f64, z: f64) -> f64 {
    value_noise_grad(seed as u32 ^ (seed >> 32) as u32, x, z).0
}

/// The 32-bit lattice seed of every octave of the fBm with scene seed `seed`.
pub fn octave_seeds(seed: u64, octaves: u32) -> Vec<u32> {
    (0..octaves)
        .map(|octave| mix64(seed.wrapping_add(u64::from(octave))) as u32)
        .collect()
}

/// The irrational offset of octave `octave`'s lattice: otherwise all octaves share lattice
/// lines through the origin and the seams line up into a grid.
pub fn octave_offset(octave: u32) -> f64 {
    f64::from(octave) * 0.618_033_988_75 + 0.25
}

/// Fractal Brownian motion of value noise in `[-1, 1]`: `octaves` layers, the first with
/// lattice spacing `wavelength`, each next one at twice the frequency and half the weight.
/// The sum is divided by the total weight so the range does not depend on `octaves`.
pub fn fbm(seed: u64, octaves: u32, wavelength: f64, x: f64, z: f64) -> f64 {
    fbm_grad(&octave_seeds(seed, octaves), wavelength, x, z).0
}

/// [`fbm`] from precomputed [`octave_seeds`], with its gradient `(∂/∂x, ∂/∂z)` in 1/m.
pub fn fbm_grad(seeds: &[u32], wavelength: f64, x: f64, z: f64) -> (f64, f64, f64) {
    let (mut sum, mut gx, mut gz) = (0.0, 0.0, 0.0);
    let mut weight = 0.0;
    let mut amplitude = 1.0;
    let mut frequency = 1.0 / wavelength;
    for (octave, &octave_seed) in seeds.iter().enumerate() {
        let offset = octave_offset(octave as u32);
        let (v, dx, dz) =
            value_noise_grad(octave_seed, x * frequency + offset, z * frequency - offset);
        sum += amplitude * v;
        gx += amplitude * dx * frequency;
        gz += amplitude * dz * frequency;
        weight += amplitude;
        amplitude *= GAIN;
        frequency *= LACUNARITY;
    }
    if weight > 0.0 {
        (sum / weight, gx / weight, gz / weight)
    } else {
        (0.0, 0.0, 0.0)
    }
}

/// An upper bound of `|∇ fbm|` (1/m) for `octaves` octaves of lattice spacing
/// `wavelength`: per octave `|∂v/∂x| ≤ 2 · max fade′ = 3.75` (two lattice values in
/// [−1, 1] apart, the quintic fade's steepest slope 15/8), the same for z, at the octave's
/// frequency and weight, over the total weight as [`fbm_grad`] divides.
pub fn fbm_max_gradient(octaves: u32, wavelength: f64) -> f64 {
    let per_octave = 2.0 * 15.0 / 8.0 * std::f64::consts::SQRT_2;
    let (mut sum, mut weight, mut amplitude, mut frequency) = (0.0, 0.0, 1.0, 1.0 / wavelength);
    for _ in 0..octaves {
        sum += amplitude * frequency * per_octave;
        weight += amplitude;
        amplitude *= GAIN;
        frequency *= LACUNARITY;
    }
    if weight > 0.0 {
        sum / weight
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_values_match_at_integer_points_and_stay_in_range() {
        for i in -5..5 {
            for j in -5..5 {
                let v = value_noise(9, f64::from(i), f64::from(j));
                assert_eq!(v, lattice(9, i, j));
                assert!((-1.0..=1.0).contains(&v));
            }
        }
    }

    #[test]
    fn noise_is_continuous() {
        // Across a lattice line the value must not jump.
        let step = 1e-6;
        for k in 0..50 {
            let z = f64::from(k) * 0.137;
            let left = value_noise(1, 3.0 - step, z);
            let right = value_noise(1, 3.0 + step, z);
            assert!((left - right).abs() < 1e-4);
        }
    }

    #[test]
    fn fbm_is_seeded_and_bounded() {
        let a = fbm(5, 4, 30.0, 1.5, -2.5);
        assert_eq!(a, fbm(5, 4, 30.0, 1.5, -2.5));
        assert_ne!(a, fbm(6, 4, 30.0, 1.5, -2.5));
        for k in 0..1000 {
            let v = fbm(5, 6, 10.0, f64::from(k) * 0.73, f64::from(k) * -0.31);
            assert!((-1.0..=1.0).contains(&v));
        }
        assert_eq!(fbm(5, 0, 10.0, 1.0, 1.0), 0.0);
    }

    #[test]
    fn gradient_matches_finite_differences() {
        let seeds = octave_seeds(3, 5);
        let h = 1e-5;
        for k in 0..200 {
            let (x, z) = (f64::from(k) * 1.37 - 90.0, f64::from(k) * -0.71 + 40.0);
            let (_, gx, gz) = fbm_grad(&seeds, 12.0, x, z);
            let fx = (fbm_grad(&seeds, 12.0, x + h, z).0 - fbm_grad(&seeds, 12.0, x - h, z).0)
                / (2.0 * h);
            let fz = (fbm_grad(&seeds, 12.0, x, z + h).0 - fbm_grad(&seeds, 12.0, x, z - h).0)
                / (2.0 * h);
            assert!(
                (gx - fx).abs() < 1e-6 && (gz - fz).abs() < 1e-6,
                "{gx} {fx} {gz} {fz}"
            );
        }
    }

    /// The WGSL `hash32` of `shaders/common.wgsl` as the adapter computes it, for the
    /// inputs `i * 2654435761` (scrambled through all 32 bits), `i < count`.
    fn wgsl_hashes(count: u32) -> Vec<u32> {
        use wgpu::util::DeviceExt;
        let gpu = crate::gpu::Gpu::new(&crate::gpu::AdapterChoice::Software)
            .expect("tests need the software adapter (CI installs lavapipe)");
        let source = crate::shaders::source("common.wgsl")
            + r#"
@group(0) @binding(0) var<storage, read_write> out: array<u32>;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    out[id.x] = hash32(id.x * 2654435761u);
}
"#;
        let device = &gpu.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("sward.test.hash"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("sward.test.hash"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let out = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sward.test.hash.out"),
            contents: &vec![0u8; count as usize * 4],
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sward.test.hash"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: out.as_entire_binding(),
            }],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(count.div_ceil(64), 1, 1);
        }
        gpu.queue.submit([encoder.finish()]);
        let bytes = crate::gpu::read_buffer(&gpu, &out, u64::from(count) * 4).expect("read");
        bytemuck::cast_slice(&bytes).to_vec()
    }

    #[test]
    fn hash_is_the_wgsl_one() {
        const COUNT: u32 = 65_536;
        let wgsl = wgsl_hashes(COUNT);
        let differing = (0..COUNT)
            .filter(|&i| wgsl[i as usize] != hash32(i.wrapping_mul(2_654_435_761)))
            .count();
        assert_eq!(differing, 0, "of {COUNT} inputs the CPU twin differs");
        // Pinned once from the WGSL on lavapipe: a change to both sides alike (which the
        // twin comparison cannot see) moves every generated field, and fails here.
        assert_eq!(
            wgsl[..6],
            [
                129_708_002,
                1_883_031_434,
                2_709_862_654,
                3_393_608_774,
                2_413_383_906,
                3_649_364_491
            ],
        );
    }
}
