// The order in which the update steps a patch's blades: by thinning class (twin:
// `sim::reference::thin_order`). Eq. 20 keeps a blade at distance d when `i mod n <
// floor(n (1 - d / d_max))`, so in a patch at some distance only its low classes are drawn.
// In the blade index order every run of 64 blades (one workgroup) holds every class, and a
// software adapter runs a workgroup whole whatever lanes return early; in class order the
// classes no blade of the patch can keep fill whole runs of their own, which the patch pass
// steps at the throttled rate (only dispatch sizes make a CPU adapter do less).
//
// Class order: the blades whose index within the patch is r mod n (class r, r < n) come
// before those of class r + 1, each class in index order. A patch of `size` blades has
// q = size / n blades in each class and one more in the first size mod n classes.

// Blades per update chunk (one workgroup of the update).
const CHUNK: u32 = 64u;

// The class of position `pos` in class order, and its rank within the class.
fn order_class(pos: u32, size: u32, n: u32) -> vec2<u32> {
    let q = size / n;
    let rem = size % n;
    let big = rem * (q + 1u);
    let t = pos - min(pos, big);
    let qs = max(q, 1u);
    let in_big = vec2<u32>(pos / (q + 1u), pos % (q + 1u));
    let in_small = vec2<u32>(rem + t / qs, t % qs);
    return select(in_small, in_big, pos < big);
}

// The blade (its index within the patch) at position `pos` of class order.
fn order_blade(pos: u32, size: u32, n: u32) -> u32 {
    let c = order_class(pos, size, n);
    return c.x + c.y * n;
}

// Whether some class of local classes [lo, hi] is one Eq. 20 keeps at `keep`, in patch
// `p`: local class r is the index class (r + p size) mod n, and the kept index classes
// 0 .. keep - 1 are the local classes from (n - p size mod n) mod n on, cyclically.
fn chunk_keeps(lo: u32, hi: u32, keep: u32, p: u32, size: u32, n: u32) -> bool {
    if keep == 0u {
        return false;
    }
    if keep >= n {
        return true;
    }
    let a = (n - (p * size) % n) % n;
    let e = a + keep;
    let first = lo < min(e, n) && hi >= a;
    let wrapped = e > n && lo < e - n;
    return first || wrapped;
}

// Whether chunk `c` of patch `p` (positions c CHUNK .. c CHUNK + CHUNK - 1 of the class
// order; patches are whole chunks) holds a class Eq. 20 keeps at `keep`.
fn chunk_kept(c: u32, keep: u32, p: u32, size: u32, n: u32) -> bool {
    let lo = order_class(c * CHUNK, size, n).x;
    let hi = order_class(c * CHUNK + CHUNK - 1u, size, n).x;
    return chunk_keeps(lo, hi, keep, p, size, n);
}
