// GPU skinning (issue 29, point 1; `render::skinning`): every vertex of an animated mesh
// object moved by its four joints' skinning matrices (linear blend skinning: the weighted
// sum of the matrices applied to the bind-pose position and normal), written into the
// object's vertex buffer (position, normal: six floats a vertex), which the colour, depth
// and shadow passes of the objects then draw. The CPU twin is `mesh::skin::SkinnedMesh::skin`
// (and `skin_normals`).

struct Influence {
    joints: vec4<u32>,
    weights: vec4<f32>,
}

// The bind pose: position and normal, six floats a vertex.
@group(0) @binding(0) var<storage, read> rest: array<f32>;
@group(0) @binding(1) var<storage, read> influence: array<Influence>;
// Per joint: its global transform at this time times its inverse bind matrix.
@group(0) @binding(2) var<storage, read> joints: array<mat4x4<f32>>;
@group(0) @binding(3) var<storage, read_write> posed: array<f32>;

@compute @workgroup_size(64)
fn skin(@builtin(global_invocation_id) id: vec3<u32>) {
    let v = id.x;
    if v >= arrayLength(&influence) {
        return;
    }
    let b = v * 6u;
    let p = vec4<f32>(rest[b], rest[b + 1u], rest[b + 2u], 1.0);
    let n = vec4<f32>(rest[b + 3u], rest[b + 4u], rest[b + 5u], 0.0);
    let inf = influence[v];
    let last = arrayLength(&joints) - 1u;
    var m = mat4x4<f32>(vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    for (var k = 0u; k < 4u; k++) {
        // Indices were checked at load; the clamp only keeps a bad one inside the array.
        m += joints[min(inf.joints[k], last)] * inf.weights[k];
    }
    let q = m * p;
    // The blended matrix's linear part turns the normal (exact for rotations and uniform
    // scales, which a skeleton's joints hold).
    let turned = (m * n).xyz;
    let len = length(turned);
    let normal = select(n.xyz, turned / len, len > 1e-8);
    posed[b] = q.x;
    posed[b + 1u] = q.y;
    posed[b + 2u] = q.z;
    posed[b + 3u] = normal.x;
    posed[b + 4u] = normal.y;
    posed[b + 5u] = normal.z;
}
