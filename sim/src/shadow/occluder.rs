//! Occluders: each shadow-casting mesh welded and split into connected components, with
//! its faces, closedness and convexity (see the module header of [`super`]).

use super::*;

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
    pub(super) edges: Vec<([DVec3; 2], Vec<usize>)>,
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
    let mut comp_of = vec![0usize; faces.len()];
    for (c, fl) in comps.iter().enumerate() {
        for &f in fl {
            comp_of[f] = c;
        }
    }
    let mut comp_edges: Vec<Vec<&(usize, usize)>> = vec![Vec::new(); comps.len()];
    for (e, fs) in &edge_faces {
        comp_edges[comp_of[fs[0]]].push(e);
    }
    comps
        .iter()
        .zip(comp_edges)
        .map(|(fl, keys)| occluder(&pos, &faces, &edge_faces, fl, keys))
        .collect()
}

/// Welds a mesh's positions bit-exactly; drops faces that become degenerate.
pub(super) fn weld(m: &crate::scene::LoadedMesh) -> (Vec<DVec3>, Vec<[usize; 3]>) {
    let mut ids: HashMap<[u64; 3], usize> = HashMap::new();
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
type EdgeFaces = HashMap<(usize, usize), Vec<usize>>;

pub(super) fn edge_faces(faces: &[[usize; 3]]) -> EdgeFaces {
    let mut edge_faces: EdgeFaces = HashMap::new();
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
/// `keys` are the component's edges: those whose first face is in `fl`.
pub(super) fn occluder(
    pos: &[DVec3],
    faces: &[[usize; 3]],
    edge_faces: &EdgeFaces,
    fl: &[usize],
    mut keys: Vec<&(usize, usize)>,
) -> Occluder {
    let local: HashMap<usize, usize> = fl.iter().enumerate().map(|(k, &f)| (f, k)).collect();
    let mut edges = Vec::new();
    let mut closed = true;
    keys.sort_unstable();
    for e in keys {
        let fs: Vec<usize> = edge_faces[e].iter().map(|f| local[f]).collect();
        closed &= fs.len() == 2;
        edges.push(([pos[e.0], pos[e.1]], fs));
    }
    let ftris: Vec<[DVec3; 3]> = fl.iter().map(|&f| faces[f].map(|i| pos[i])).collect();
    let convex = closed && is_convex(&ftris);
    Occluder {
        faces: ftris,
        convex_closed: convex,
        closed,
        edges,
    }
}

/// Every vertex lies on one side of every face's plane (within a relative 1e-9).
pub(super) fn is_convex(ftris: &[[DVec3; 3]]) -> bool {
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
}
