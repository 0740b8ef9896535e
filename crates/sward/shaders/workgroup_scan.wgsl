// An exclusive prefix sum over one workgroup of SCAN_THREADS invocations, each summing a
// contiguous slice of the items first (`scan_slice`): the passes that put a list in a fixed
// order whatever order the workgroups ran in (`cull_order.wgsl`, `billboard_cull.wgsl`)
// turn their workgroups' counts into offsets with it.

const SCAN_THREADS: u32 = 256u;

var<workgroup> partial: array<vec3<u32>, 257>;

// The items [x, y) of `count` that invocation `t` sums: contiguous, in order.
fn scan_slice(t: u32, count: u32) -> vec2<u32> {
    let span = (count + SCAN_THREADS - 1u) / SCAN_THREADS;
    let lo = min(t * span, count);
    return vec2<u32>(lo, min(lo + span, count));
}

// The sum of `v` over the invocations before `t`; `partial[SCAN_THREADS]` holds the total
// afterwards. In uniform control flow only (two barriers).
fn exclusive_scan(t: u32, v: vec3<u32>) -> vec3<u32> {
    partial[t] = v;
    workgroupBarrier();
    if t == 0u {
        var run = vec3<u32>(0u);
        for (var k = 0u; k < SCAN_THREADS; k++) {
            let x = partial[k];
            partial[k] = run;
            run += x;
        }
        partial[SCAN_THREADS] = run;
    }
    workgroupBarrier();
    return partial[t];
}
