//! `div_small` (common.wgsl): the grass vertex stage's small integer quotients taken in
//! float, since a software rasteriser divides integer vectors lane by lane. Its comment
//! claims the quotient is exact while a + 1/2 < 2^23; the GPU's answers are held to integer
//! division over every a below 4,096 with every divisor the vertex stage uses (up to 64),
//! and at the claim's edge, the largest a, against divisors up to a million.

mod common;

/// The GPU's `div_small(a, b)` for each pair.
fn gpu_quotients(gpu: &sward::gpu::Gpu, pairs: &[(u32, u32)]) -> Vec<u32> {
    let flat: Vec<[u32; 4]> = pairs.iter().map(|&(a, b)| [a, b, 0, 0]).collect();
    let out = sward::gpu::run_vec4_probe(
        gpu,
        "sward.test.div_small",
        "div_small_probe.wgsl",
        &[bytemuck::cast_slice(&flat)],
        pairs.len(),
    )
    .expect("probe");
    out.iter().map(|v| v[0] as u32).collect()
}

fn check(gpu: &sward::gpu::Gpu, pairs: &[(u32, u32)]) {
    let got = gpu_quotients(gpu, pairs);
    let wrong: Vec<_> = pairs
        .iter()
        .zip(&got)
        .filter(|((a, b), q)| a / b != **q)
        .take(5)
        .collect();
    assert!(
        wrong.is_empty(),
        "div_small differs from a / b at {wrong:?}"
    );
}

#[test]
fn small_quotients_are_exact() {
    let gpu = common::gpu();
    let pairs: Vec<(u32, u32)> = (1..=64u32)
        .flat_map(|b| (0..4096u32).map(move |a| (a, b)))
        .collect();
    check(&gpu, &pairs);
}

#[test]
fn quotients_are_exact_up_to_the_claimed_bound() {
    let gpu = common::gpu();
    // a + 1/2 < 2^23: the largest a, and the numbers around every multiple of b near it
    // (where a quotient's rounding would show first).
    let top = (1u32 << 23) - 1;
    let mut pairs = Vec::new();
    for b in [1u32, 2, 3, 7, 51, 64, 1000, 4095, 65_537, 1_000_003] {
        let q = top / b;
        for k in q.saturating_sub(2)..=q {
            let m = k * b;
            for a in [m.saturating_sub(1), m, m + 1, m + b - 1] {
                if a <= top {
                    pairs.push((a, b));
                }
            }
        }
        pairs.push((top, b));
    }
    check(&gpu, &pairs);
}
