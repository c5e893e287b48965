//! Occluders: each shadow-casting mesh welded and split into connected components, with
//! its faces, closedness and convexity (see the module header of [`super`]).

use super::*;
use ahash::AHashMap;
use smallvec::SmallVec;

/// The faces on one welded edge: two on a closed surface.
pub(super) type EdgeFaceList = SmallVec<[usize; 2]>;

/// An occluder in world space: triangles and, per volume, the polygons to extrude.
#[derive(Clone, Debug)]
pub struct Occluder {
    /// Faces of the component (for the eye-inside test).
    pub faces: Vec<[DVec3; 3]>,
    /// Closed and convex: one silhouette volume; else one volume per face.
    pub convex_closed: bool,
    /// Closed (every edge shared by exactly two faces).
    pub closed: bool,
    /// Welded edges: vertex pairs and their adjacent faces.
    pub(super) edges: Vec<([DVec3; 2], EdgeFaceList)>,
}

/// Splits every shadow-casting mesh into connected components (meshes in parallel; the
/// occluders in mesh order, then component order).
pub fn occluders(ls: &LoadedScene) -> Vec<Occluder> {
    let per_mesh: Vec<Vec<Occluder>> = ls
        .meshes
        .par_iter()
        .zip(&ls.scene.meshes)
        .map(|(m, mr)| {
            if mr.casts_shadows {
                mesh_occluders(m)
            } else {
                Vec::new()
            }
        })
        .collect();
    per_mesh.concat()
}

/// One mesh's occluders, one per connected component.
fn mesh_occluders(m: &crate::scene::LoadedMesh) -> Vec<Occluder> {
    let (pos, faces) = weld(m);
    let edge_faces = edge_faces(&faces);
    let comps = components(faces.len(), &edge_faces);
    // Each component's edges (those whose first face is in it), in one pass over the
    // edges rather than one per component.
    // And each face's place in its component's list: its index in that occluder.
    let (mut comp_of, mut local) = (vec![0usize; faces.len()], vec![0usize; faces.len()]);
    for (c, fl) in comps.iter().enumerate() {
        for (k, &f) in fl.iter().enumerate() {
            comp_of[f] = c;
            local[f] = k;
        }
    }
    let mut comp_edges: Vec<Vec<&(usize, usize)>> = vec![Vec::new(); comps.len()];
    for (e, fs) in &edge_faces {
        comp_edges[comp_of[fs[0]]].push(e);
    }
    comps
        .iter()
        .zip(comp_edges)
        .map(|(fl, keys)| occluder(&pos, &faces, &edge_faces, &local, fl, keys))
        .collect()
}

/// Welds a mesh's positions bit-exactly; drops faces that become degenerate.
pub(super) fn weld(m: &crate::scene::LoadedMesh) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let mut ids: AHashMap<[u64; 3], usize> = AHashMap::new();
    let mut pos = Vec::new();
    let mut weld = |p: [f64; 3]| {
        *ids.entry(p.map(f64::to_bits)).or_insert_with(|| {
            pos.push(DVec3::from(p));
            pos.len() - 1
        })
    };
    let faces: Vec<[usize; 3]> = m
        .triangles
        .iter()
        .map(|t| t.map(|i| weld(m.positions[i as usize])))
        .filter(|f| f[0] != f[1] && f[1] != f[2] && f[0] != f[2])
        .collect();
    (pos, faces)
}

/// Faces adjacent to each undirected edge (vertex pair, smaller index first).
type EdgeFaces = AHashMap<(usize, usize), EdgeFaceList>;

pub(super) fn edge_faces(faces: &[[usize; 3]]) -> EdgeFaces {
    let mut edge_faces: EdgeFaces = AHashMap::new();
    for (fi, f) in faces.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            edge_faces.entry((a.min(b), a.max(b))).or_default().push(fi);
        }
    }
    edge_faces
}

/// Connected components of faces sharing an edge (union-find), each in ascending face
/// order, ordered by their smallest face (the same in every run).
pub(super) fn components(n: usize, edge_faces: &EdgeFaces) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        let mut y = x;
        while p[y] != r {
            let n = p[y];
            p[y] = r;
            y = n;
        }
        r
    }
    for fs in edge_faces.values() {
        for w in fs.windows(2) {
            let (a, b) = (find(&mut parent, w[0]), find(&mut parent, w[1]));
            parent[a] = b;
        }
    }
    // Numbered in order of their smallest face: the union order above follows the hash
    // map's iteration, which differs between runs, and so does which face becomes a root.
    let mut id = vec![usize::MAX; n];
    let mut comps: Vec<Vec<usize>> = Vec::new();
    for fi in 0..n {
        let r = find(&mut parent, fi);
        if id[r] == usize::MAX {
            id[r] = comps.len();
            comps.push(Vec::new());
        }
        comps[id[r]].push(fi);
    }
    comps
}

/// One component as an occluder: its faces, welded edges, closed and convex tests.
/// `keys` are the component's edges: those whose first face is in `fl`; `local[f]` is
/// face `f`'s index in its component's list.
pub(super) fn occluder(
    pos: &[DVec3],
    faces: &[[usize; 3]],
    edge_faces: &EdgeFaces,
    local: &[usize],
    fl: &[usize],
    mut keys: Vec<&(usize, usize)>,
) -> Occluder {
    let mut edges = Vec::new();
    let mut closed = true;
    keys.sort_unstable();
    for e in keys {
        let fs: EdgeFaceList = edge_faces[e].iter().map(|&f| local[f]).collect();
        closed &= fs.len() == 2;
        edges.push(([pos[e.0], pos[e.1]], fs));
    }
    let ftris: Vec<[DVec3; 3]> = fl.iter().map(|&f| faces[f].map(|i| pos[i])).collect();
    let convex = closed && {
        // The component's positions, each once: welding made equal positions (to the
        // bit) one index, so distinct indices are the distinct positions `is_convex`
        // finds by sorting the coordinates' bits, found here by sorting integers.
        let mut ids: Vec<usize> = fl.iter().flat_map(|&f| faces[f]).collect();
        ids.sort_unstable();
        ids.dedup();
        is_convex_over(&ftris, ids.into_iter().map(|i| pos[i]).collect())
    };
    Occluder {
        faces: ftris,
        convex_closed: convex,
        closed,
        edges,
    }
}

/// Every vertex lies on one side of every face's plane (within a relative 1e-9): for
/// every face with unit normal `n`, `(v − t0)·n ≤ ε` for every vertex `v` or `≥ −ε` for
/// every vertex, `ε = 1e-9 · max(1, largest |coordinate|)`, in `f64` as written.
///
/// The same predicate as the literal double loop over faces and vertices, without its
/// faces × vertices cost (a 5k-triangle sphere took 80 ms): the vertices (each position
/// once) are kept in a bounding-box tree ([`VertexTree`]), and a box whose every point is
/// provably on the tested side by more than the rounding of the per-vertex expression
/// passes without evaluating its vertices; the others are evaluated exactly as written.
/// (The occluders call [`is_convex_over`] with the welded positions.)
#[cfg(test)]
fn is_convex(ftris: &[[DVec3; 3]]) -> bool {
    let mut verts: Vec<DVec3> = ftris.iter().flatten().copied().collect();
    // Each position once: a vertex repeated changes neither `all`.
    let bits = |v: &DVec3| v.to_array().map(f64::to_bits);
    verts.sort_unstable_by_key(bits);
    verts.dedup_by_key(|v| bits(v));
    is_convex_over(ftris, verts)
}

/// [`is_convex`] of `ftris` given `verts`, the positions of their corners, each once
/// (in any order).
pub(super) fn is_convex_over(ftris: &[[DVec3; 3]], verts: Vec<DVec3>) -> bool {
    let scale = verts
        .iter()
        .fold(0.0f64, |s, v| s.max(v.abs().max_element()))
        .max(1.0);
    let eps = 1e-9 * scale;
    if !verts.iter().all(|v| v.is_finite()) {
        return ftris.iter().all(|t| face_splits_none(t, &verts, eps, None));
    }
    let tree = VertexTree::new(verts);
    ftris
        .iter()
        .all(|t| face_splits_none(t, &tree.verts, eps, Some((&tree, scale))))
}

/// One face of [`is_convex`]: every vertex on one side of its plane within `eps`, the
/// vertices' boxes of `tree` (with the coordinates' `scale`) culling where they can.
fn face_splits_none(
    t: &[DVec3; 3],
    verts: &[DVec3],
    eps: f64,
    tree: Option<(&VertexTree, f64)>,
) -> bool {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    let len = n.length();
    // `len > 0` fails for zero and NaN alike.
    if len.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return false;
    }
    let n = n / len;
    let side = |v: &DVec3| (*v - t[0]).dot(n);
    match tree {
        Some((tree, scale)) if n.is_finite() => {
            tree.all_within(t[0], n, scale, eps, 1.0) || tree.all_within(t[0], n, scale, eps, -1.0)
        }
        _ => verts.iter().all(|v| side(v) <= eps) || verts.iter().all(|v| side(v) >= -eps),
    }
}

/// Vertices in a binary tree of axis-aligned bounding boxes (leaves of at most
/// [`VertexTree::LEAF`] vertices), for [`is_convex`]'s culled test.
struct VertexTree {
    /// The vertices, reordered so that each node's are contiguous.
    verts: Vec<DVec3>,
    /// Their coordinates, one list per axis (a leaf's vertices are then tested several
    /// at a time).
    xyz: [Vec<f64>; 3],
    /// Nodes: box centre, half extent, vertex range, children (0 for a leaf).
    nodes: Vec<BoxNode>,
}

#[derive(Clone, Copy)]
struct BoxNode {
    centre: DVec3,
    half: DVec3,
    range: (u32, u32),
    kids: (u32, u32),
}

impl VertexTree {
    /// Most vertices in a leaf.
    const LEAF: usize = 32;

    fn new(mut verts: Vec<DVec3>) -> Self {
        let mut nodes = Vec::with_capacity(2 * verts.len() / Self::LEAF + 1);
        Self::build(&mut verts, 0, &mut nodes);
        let xyz = [0, 1, 2].map(|k| verts.iter().map(|v| v[k]).collect());
        VertexTree { verts, xyz, nodes }
    }

    /// Builds the node of `verts` (starting at index `at` of the whole list) and its
    /// subtree; returns its index.
    fn build(verts: &mut [DVec3], at: usize, nodes: &mut Vec<BoxNode>) -> u32 {
        let (lo, hi) = verts.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), v| (lo.min(*v), hi.max(*v)),
        );
        let me = nodes.len();
        nodes.push(BoxNode {
            centre: (lo + hi) * 0.5,
            half: (hi - lo) * 0.5,
            range: (at as u32, (at + verts.len()) as u32),
            kids: (0, 0),
        });
        if verts.len() > Self::LEAF {
            let ext = hi - lo;
            let axis = if ext.x >= ext.y && ext.x >= ext.z {
                0
            } else if ext.y >= ext.z {
                1
            } else {
                2
            };
            let mid = verts.len() / 2;
            verts.select_nth_unstable_by(mid, |a, b| a[axis].total_cmp(&b[axis]));
            let (a, b) = verts.split_at_mut(mid);
            let l = Self::build(a, at, nodes);
            let r = Self::build(b, at + mid, nodes);
            nodes[me].kids = (l, r);
        }
        me as u32
    }

    /// Whether `sign · side(v) ≤ eps` for every vertex (`sign` ±1; `side(v)` is
    /// `(v − p)·n` as [`face_splits_none`] computes it, `n` a unit normal, every coordinate
    /// within `scale`). A box passes unopened when the exact maximum of `sign · (x − p)·n`
    /// over it, bounded from above with room for the rounding of both that bound and
    /// `side`, is at most `eps`. A leaf's vertices are evaluated with the same operations
    /// in the same order as `side` (glam's `DVec3` subtraction and `dot`:
    /// `((dx·nx) + (dy·ny)) + (dz·nz)`), so to the same bits.
    fn all_within(&self, p: DVec3, n: DVec3, scale: f64, eps: f64, sign: f64) -> bool {
        // |side(v) − (v − p)·n| and the rounding of the bound below are each under
        // 1e-14 · scale (a handful of roundings of terms below 4 · scale, |n| ≈ 1); the
        // slack is a thousand times more and a thousand times less than eps.
        let slack = 1e-12 * scale;
        // Depth first, on the stack: at most one pending sibling per level, and the tree
        // (median splits down to LEAF vertices) is under 40 levels deep for any `u32` count.
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let b = &self.nodes[stack[top] as usize];
            let bound = sign * (b.centre - p).dot(n) + b.half.dot(n.abs());
            if bound + slack <= eps {
                continue;
            }
            if b.kids.0 == 0 {
                let (s, e) = (b.range.0 as usize, b.range.1 as usize);
                let [xs, ys, zs] = [0, 1, 2].map(|k| &self.xyz[k][s..e]);
                // No early exit inside a leaf: the loop runs several vertices at a time.
                let mut ok = true;
                for ((x, y), z) in xs.iter().zip(ys).zip(zs) {
                    let side = (x - p.x) * n.x + (y - p.y) * n.y + (z - p.z) * n.z;
                    ok &= sign * side <= eps;
                }
                if !ok {
                    return false;
                }
            } else {
                stack[top] = b.kids.1;
                stack[top + 1] = b.kids.0;
                top += 2;
            }
        }
        true
    }
}

pub(super) fn facing(t: &[DVec3; 3], light: DVec3) -> f64 {
    let n = (t[1] - t[0]).cross(t[2] - t[0]);
    n.dot(light - (t[0] + t[1] + t[2]) / 3.0)
}

/// Segment–triangle intersection (Möller–Trumbore), strictly inside `(0, 1)` of the segment.
pub(super) fn segment_hits(p: DVec3, q: DVec3, t: &[DVec3; 3]) -> bool {
    let d = q - p;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let h = d.cross(e2);
    let a = e1.dot(h);
    if a.abs() < 1e-14 {
        return false;
    }
    let f = 1.0 / a;
    let s = p - t[0];
    let u = f * s.dot(h);
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = s.cross(e1);
    let v = f * d.dot(qv);
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let tt = f * e2.dot(qv);
    tt > 1e-9 && tt < 1.0 - 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Six "stars" (a face and the three faces on its edges), their faces shuffled through
    /// the face list. Which face of a star ends up as the union-find root depends on the
    /// order its edges are visited, and every call builds a new hash map, whose iteration
    /// order differs from the last one's; the components and their order must not.
    #[test]
    fn components_come_in_the_same_order_every_time() {
        let (stars, per) = (6usize, 4usize);
        let n = stars * per;
        // Item `i` (star `i / 4`, role `i % 4`) becomes face `(7 i) mod 24`.
        let face_of = |i: usize| (7 * i) % n;
        let mut faces = vec![[0usize; 3]; n];
        for i in 0..n {
            let b = 10 * (i / per);
            faces[face_of(i)] = match i % per {
                0 => [b, b + 1, b + 2],
                1 => [b + 1, b, b + 3],
                2 => [b + 2, b + 1, b + 4],
                _ => [b, b + 2, b + 5],
            };
        }
        let mut expected: Vec<Vec<usize>> = (0..stars)
            .map(|s| {
                let mut fl: Vec<usize> = (0..per).map(|r| face_of(s * per + r)).collect();
                fl.sort_unstable();
                fl
            })
            .collect();
        expected.sort_unstable_by_key(|fl| fl[0]);
        for _ in 0..64 {
            let ef = edge_faces(&faces);
            assert_eq!(components(n, &ef), expected);
        }
    }

    /// The literal predicate [`is_convex`] states: every face against every vertex.
    fn is_convex_literal(ftris: &[[DVec3; 3]]) -> bool {
        let verts: Vec<DVec3> = ftris.iter().flatten().copied().collect();
        let scale = verts
            .iter()
            .fold(0.0f64, |s, v| s.max(v.abs().max_element()))
            .max(1.0);
        ftris.iter().all(|t| {
            let n = (t[1] - t[0]).cross(t[2] - t[0]);
            let len = n.length();
            len > 0.0 && {
                let n = n / len;
                let side = |v: &DVec3| (*v - t[0]).dot(n);
                let eps = 1e-9 * scale;
                verts.iter().all(|v| side(v) <= eps) || verts.iter().all(|v| side(v) >= -eps)
            }
        })
    }

    /// The tree's leaf evaluation is the face test's own expression to the bit: with `eps`
    /// set to the largest `sign · side(v)` over random point clouds (`side` as
    /// [`face_splits_none`] writes it), every vertex passes, and with the next smaller
    /// `eps` one fails. A different rounding of the vertex that sets the maximum, or a
    /// strict comparison, fails this.
    #[test]
    fn leaf_sides_are_the_face_tests_to_the_bit() {
        let mut rng = crate::rng::XorShift64Star(0x1eaf);
        for trial in 0..400 {
            let s = [1e-3, 1.0, 7.5, 1e5][trial % 4];
            let count = 1 + (rng.next_u64() % 300) as usize;
            let mut r = || (rng.unit() - 0.5) * 2.0 * s;
            let pts: Vec<DVec3> = (0..count).map(|_| DVec3::new(r(), r(), r())).collect();
            let p = pts[trial % count];
            let n = DVec3::new(r(), r(), r()).normalize();
            let scale = pts
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs().max_element()))
                .max(1.0);
            let side = |v: &DVec3| (*v - p).dot(n);
            let tree = VertexTree::new(pts.clone());
            for sign in [1.0, -1.0] {
                let eps = pts
                    .iter()
                    .map(|v| sign * side(v))
                    .fold(f64::NEG_INFINITY, f64::max);
                assert!(tree.all_within(p, n, scale, eps, sign), "trial {trial}");
                assert!(
                    !tree.all_within(p, n, scale, eps.next_down(), sign),
                    "trial {trial}"
                );
            }
        }
    }

    /// A sphere's surface: the octahedron's faces subdivided `level` times, the vertices
    /// pushed onto the unit sphere (convex, many faces).
    fn sphere(level: u32) -> Vec<[DVec3; 3]> {
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        let mut f = vec![];
        for sx in [1.0, -1.0] {
            for sy in [1.0, -1.0] {
                for sz in [1.0, -1.0] {
                    let t = [x * sx, y * sy, z * sz];
                    // Outward winding for every octant.
                    f.push(if sx * sy * sz > 0.0 {
                        t
                    } else {
                        [t[0], t[2], t[1]]
                    });
                }
            }
        }
        for _ in 0..level {
            f = f
                .iter()
                .flat_map(|&[a, b, c]| {
                    let m = |p: DVec3, q: DVec3| ((p + q) * 0.5).normalize();
                    let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
                    [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
                })
                .collect();
        }
        f
    }

    /// A box with `k × k` squares per side (two triangles each): vertices inside every
    /// face, so every face has vertices on its own plane (side 0, within rounding).
    fn tiled_box(k: usize) -> Vec<[DVec3; 3]> {
        let mut f = vec![];
        for axis in 0..3 {
            for s in [-1.0, 1.0] {
                let p = |u: usize, v: usize| {
                    let (u, v) = (
                        2.0 * u as f64 / k as f64 - 1.0,
                        2.0 * v as f64 / k as f64 - 1.0,
                    );
                    let mut c = [0.0; 3];
                    c[axis] = s;
                    c[(axis + 1) % 3] = u;
                    c[(axis + 2) % 3] = v;
                    DVec3::from(c)
                };
                for i in 0..k {
                    for j in 0..k {
                        f.push([p(i, j), p(i + 1, j), p(i + 1, j + 1)]);
                        f.push([p(i, j), p(i + 1, j + 1), p(i, j + 1)]);
                    }
                }
            }
        }
        f
    }

    /// The culled test gives the literal predicate's answer: on convex surfaces at scales
    /// from 1e-3 to 1e7, offset from the origin (true); with one vertex moved out of its
    /// neighbours' planes by less than, about, and more than the tolerance ε (both
    /// answers, the boundary evaluated exactly); on shuffled and flipped faces; on random
    /// triangle soups (false); and on faces with degenerate or non-finite corners.
    #[test]
    fn culled_convexity_is_the_literal_predicate() {
        let mut rng = crate::rng::XorShift64Star(0xc0_0e_e5);
        let mut shapes: Vec<Vec<[DVec3; 3]>> =
            vec![sphere(0), sphere(2), sphere(4), tiled_box(1), tiled_box(5)];
        shapes.push(
            sphere(3)
                .into_iter()
                .chain(tiled_box(2).into_iter().map(|t| t.map(|v| v * 0.5)))
                .collect(),
        );
        let (mut yes, mut no) = (0, 0);
        for shape in &shapes {
            for case in 0..40 {
                let scale = [1e-3, 0.7, 1.0, 3.0, 250.0, 1e7][case % 6];
                let offset = DVec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5)
                    * scale
                    * [0.0, 1.0, 5.0][case % 3];
                let mut t: Vec<[DVec3; 3]> = shape
                    .iter()
                    .map(|t| t.map(|v| v * scale + offset))
                    .collect();
                if case % 4 == 1 {
                    // One vertex pushed outward by a multiple of ε around 1 (every face
                    // holding it moves with it).
                    let eps = 1e-9
                        * t.iter()
                            .flatten()
                            .fold(1.0f64, |s, v| s.max(v.abs().max_element()));
                    let pick = t[(rng.next_u64() % t.len() as u64) as usize][0];
                    let k = [0.3, 0.999, 1.0, 1.001, 2.0, 50.0][(rng.next_u64() % 6) as usize];
                    let out = pick + (pick - offset).normalize() * eps * k;
                    for f in t.iter_mut().flatten() {
                        if *f == pick {
                            *f = out;
                        }
                    }
                }
                if case % 5 == 2 {
                    // Shuffled order, some faces flipped: the predicate takes either side.
                    for i in (1..t.len()).rev() {
                        t.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
                    }
                    for f in t.iter_mut().step_by(3) {
                        f.swap(1, 2);
                    }
                }
                let want = is_convex_literal(&t);
                assert_eq!(
                    is_convex(&t),
                    want,
                    "shape of {} faces, case {case}",
                    t.len()
                );
                // The occluders' form: the distinct positions in another order (last
                // appearance first), as welding lists them.
                let mut distinct: Vec<DVec3> = Vec::new();
                for v in t.iter().flatten().rev() {
                    if !distinct
                        .iter()
                        .any(|d| d.to_array().map(f64::to_bits) == v.to_array().map(f64::to_bits))
                    {
                        distinct.push(*v);
                    }
                }
                assert_eq!(is_convex_over(&t, distinct), want, "case {case}, welded");
                if want {
                    yes += 1;
                } else {
                    no += 1;
                }
            }
        }
        for _ in 0..200 {
            let n = 1 + (rng.next_u64() % 40) as usize;
            let t: Vec<[DVec3; 3]> = (0..n)
                .map(|_| [0; 3].map(|_| DVec3::new(rng.unit(), rng.unit(), rng.unit()) * 10.0))
                .collect();
            assert_eq!(is_convex(&t), is_convex_literal(&t));
        }
        let o = DVec3::ZERO;
        for odd in [
            vec![[o, DVec3::X, DVec3::X * 2.0]],
            vec![[o, DVec3::X, DVec3::new(f64::NAN, 0.0, 1.0)]],
            vec![
                [o, DVec3::X, DVec3::Y],
                [o, DVec3::Y, DVec3::new(f64::INFINITY, 1.0, 1.0)],
            ],
        ] {
            assert_eq!(is_convex(&odd), is_convex_literal(&odd), "{odd:?}");
        }
        assert!(yes >= 100 && no >= 40, "{yes} convex, {no} not");
    }
}
