//! Static instances in a chunk grid with an octree per chunk (Tachyon; Preißner 2020 §3.2), traversed
//! in parallel. Objects are stored in depth-first order, so every subtree owns one contiguous
//! range: a node entirely inside the view is accepted as a single range — a draw-call-sized
//! unit — without testing its objects.

use std::ops::Range;

use glam::Vec3;
use rayon::prelude::*;

use super::{Aabb, Relation, Sphere, SphereSoa, StereoCull};

/// How the hierarchy is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HierarchyParams {
    /// Edge length of a grid chunk (Tachyon: 80 units).
    pub chunk_size: f32,
    /// Octree depth below the chunk root.
    pub max_depth: u32,
    /// A node with at most this many objects is not split.
    pub leaf_capacity: usize,
}

impl Default for HierarchyParams {
    fn default() -> Self {
        HierarchyParams {
            chunk_size: 80.0,
            max_depth: 4,
            leaf_capacity: 48,
        }
    }
}

#[derive(Clone, Debug)]
struct Node {
    bounds: Aabb,
    /// Objects stored at this node (too large for any child octant).
    own: Range<u32>,
    /// End of this node's subtree's objects (they start at `own.start`).
    subtree_end: u32,
    /// Child node indices within the chunk.
    children: Vec<u32>,
}

#[derive(Clone, Debug)]
struct Chunk {
    nodes: Vec<Node>,
}

impl Chunk {
    fn bounds(&self) -> Aabb {
        self.nodes[0].bounds
    }
}

/// What one culling pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CullStats {
    /// Chunks within the draw distance.
    pub chunks: u64,
    /// Node (box) tests run.
    pub node_tests: u64,
    /// Object (sphere) tests run.
    pub object_tests: u64,
    /// Objects accepted.
    pub visible: u64,
    /// Accepted objects no eye can see (exact `f64` per-eye reference), when measured.
    pub false_positives: Option<u64>,
    /// Objects some eye can see that were rejected, when measured (round robin's misses, the
    /// lens-hidden corners for dual cones).
    pub misses: Option<u64>,
}

impl CullStats {
    fn add(mut self, o: CullStats) -> CullStats {
        self.chunks += o.chunks;
        self.node_tests += o.node_tests;
        self.object_tests += o.object_tests;
        self.visible += o.visible;
        self
    }
}

/// Accepted objects as ranges of the hierarchy's object order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VisibleSet {
    /// The ranges, in order, none empty.
    pub ranges: Vec<Range<u32>>,
}

impl VisibleSet {
    /// How many objects were accepted.
    pub fn len(&self) -> u64 {
        self.ranges.iter().map(|r| (r.end - r.start) as u64).sum()
    }

    /// Whether none was.
    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// The accepted objects' positions in the hierarchy's order (see [`CullHierarchy::ids`]).
    pub fn indices(&self) -> impl Iterator<Item = u32> + '_ {
        self.ranges.iter().flat_map(|r| r.clone())
    }

    fn push_index(&mut self, i: u32) {
        match self.ranges.last_mut() {
            Some(last) if last.end == i => last.end += 1,
            _ => self.ranges.push(i..i + 1),
        }
    }
}

/// The result of culling one frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CullResult {
    /// What was accepted.
    pub visible: VisibleSet,
    /// How the traversal went.
    pub stats: CullStats,
}

/// The static scene's bounds, organised for culling.
pub struct CullHierarchy {
    chunks: Vec<Chunk>,
    /// Bounds in hierarchy order.
    pub spheres: SphereSoa,
    /// Original instance index of each object in hierarchy order.
    pub ids: Vec<u32>,
}

impl CullHierarchy {
    /// The hierarchy over `spheres` (one per object): a grid of chunks, an octree in each.
    pub fn build(spheres: &[Sphere], params: HierarchyParams) -> Self {
        let size = params.chunk_size;
        let key = |c: Vec3| {
            let k = (c / size).floor();
            (k.x as i32, k.y as i32, k.z as i32)
        };
        let mut order: Vec<u32> = (0..spheres.len() as u32).collect();
        order.par_sort_unstable_by_key(|&i| key(spheres[i as usize].center));
        // Split into runs of the same chunk key.
        let mut runs: Vec<Range<usize>> = Vec::new();
        let mut start = 0;
        for i in 1..=order.len() {
            if i == order.len()
                || key(spheres[order[i] as usize].center)
                    != key(spheres[order[start] as usize].center)
            {
                if i > start {
                    runs.push(start..i);
                }
                start = i;
            }
        }
        let built: Vec<(Chunk, Vec<u32>)> = runs
            .par_iter()
            .map(|run| {
                let members = &order[run.clone()];
                let k = key(spheres[members[0] as usize].center);
                let min = Vec3::new(k.0 as f32, k.1 as f32, k.2 as f32) * size;
                build_chunk(spheres, members.to_vec(), min, size, params)
            })
            .collect();
        let mut chunks = Vec::with_capacity(built.len());
        let mut ids = Vec::with_capacity(spheres.len());
        let mut soa = SphereSoa::with_capacity(spheres.len());
        for (mut chunk, local) in built {
            let base = ids.len() as u32;
            for node in &mut chunk.nodes {
                node.own = node.own.start + base..node.own.end + base;
                node.subtree_end += base;
            }
            for &i in &local {
                soa.push(spheres[i as usize]);
            }
            ids.extend(local);
            chunks.push(chunk);
        }
        CullHierarchy {
            chunks,
            spheres: soa,
            ids,
        }
    }

    /// How many objects it holds.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// How many grid chunks it has.
    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// The objects `culler` accepts within `draw_distance` of `eye_centre` (distance culling at
    /// chunk, node and object level), chunks in parallel.
    pub fn cull<C: StereoCull>(
        &self,
        culler: &C,
        eye_centre: Vec3,
        draw_distance: f32,
    ) -> CullResult {
        let reach = |b: &Aabb| distance_relation(b, eye_centre, draw_distance);
        let results: Vec<CullResult> = self
            .chunks
            .par_iter()
            .filter(|c| reach(&c.bounds()) != Relation::Outside)
            .map(|chunk| self.cull_chunk(chunk, culler, eye_centre, draw_distance))
            .collect();
        let mut out = CullResult::default();
        for r in results {
            out.stats = out.stats.add(r.stats);
            out.visible.ranges.extend(r.visible.ranges);
        }
        out
    }

    fn cull_chunk<C: StereoCull>(
        &self,
        chunk: &Chunk,
        culler: &C,
        eye: Vec3,
        distance: f32,
    ) -> CullResult {
        let mut result = CullResult::default();
        result.stats.chunks = 1;
        let mut stack = vec![0u32];
        let mut accepted = Vec::new();
        let max_d = |r: f32| (distance + r) * (distance + r);
        while let Some(n) = stack.pop() {
            let node = &chunk.nodes[n as usize];
            result.stats.node_tests += 1;
            let relation = culler.aabb(&node.bounds).intersection(distance_relation(
                &node.bounds,
                eye,
                distance,
            ));
            match relation {
                Relation::Outside => {}
                Relation::Inside => result.visible.ranges.push(node.own.start..node.subtree_end),
                Relation::Intersecting => {
                    let own = node.own.start as usize..node.own.end as usize;
                    result.stats.object_tests += own.len() as u64;
                    accepted.clear();
                    culler.spheres(&self.spheres, own, &mut accepted);
                    for &i in &accepted {
                        let s = self.spheres.get(i as usize);
                        if (s.center - eye).length_squared() <= max_d(s.radius) {
                            result.visible.push_index(i);
                        }
                    }
                    stack.extend(node.children.iter().rev());
                }
            }
        }
        result.stats.visible = result.visible.len();
        result
    }
}

/// Where a box lies relative to the ball of radius `distance` around `eye`.
fn distance_relation(b: &Aabb, eye: Vec3, distance: f32) -> Relation {
    let d2 = distance * distance;
    if b.distance_squared(eye) > d2 {
        Relation::Outside
    } else if b
        .corners()
        .iter()
        .all(|c| (*c - eye).length_squared() <= d2)
    {
        Relation::Inside
    } else {
        Relation::Intersecting
    }
}

/// Builds one chunk's octree; returns it with its objects in depth-first order (chunk-local
/// `own` ranges).
fn build_chunk(
    spheres: &[Sphere],
    members: Vec<u32>,
    min: Vec3,
    size: f32,
    params: HierarchyParams,
) -> (Chunk, Vec<u32>) {
    let mut chunk = Chunk { nodes: Vec::new() };
    let mut order = Vec::with_capacity(members.len());
    build_node(
        spheres, members, min, size, 0, params, &mut chunk, &mut order,
    );
    (chunk, order)
}

#[allow(clippy::too_many_arguments)]
fn build_node(
    spheres: &[Sphere],
    members: Vec<u32>,
    min: Vec3,
    size: f32,
    depth: u32,
    params: HierarchyParams,
    chunk: &mut Chunk,
    order: &mut Vec<u32>,
) -> u32 {
    let index = chunk.nodes.len() as u32;
    chunk.nodes.push(Node {
        bounds: Aabb::EMPTY,
        own: 0..0,
        subtree_end: 0,
        children: Vec::new(),
    });
    let half = size * 0.5;
    let mut own = Vec::new();
    let mut octants: [Vec<u32>; 8] = Default::default();
    if depth >= params.max_depth || members.len() <= params.leaf_capacity {
        own = members;
    } else {
        // Size-aware insertion: an object goes down only if its box fits one octant.
        for i in members {
            let b = Aabb::of_sphere(&spheres[i as usize]);
            let lo = ((b.min - min) / half).floor();
            let hi = ((b.max - min) / half).floor();
            if lo == hi && lo.cmpge(Vec3::ZERO).all() && lo.cmple(Vec3::ONE).all() {
                octants[(lo.x as usize) | (lo.y as usize) << 1 | (lo.z as usize) << 2].push(i);
            } else {
                own.push(i);
            }
        }
    }
    let start = order.len() as u32;
    let mut bounds = Aabb::EMPTY;
    for &i in &own {
        bounds = bounds.union(&Aabb::of_sphere(&spheres[i as usize]));
    }
    order.extend_from_slice(&own);
    let own_range = start..order.len() as u32;
    let mut children = Vec::new();
    for (o, objs) in octants.into_iter().enumerate() {
        if objs.is_empty() {
            continue;
        }
        let offset = Vec3::new((o & 1) as f32, ((o >> 1) & 1) as f32, ((o >> 2) & 1) as f32) * half;
        let child = build_node(
            spheres,
            objs,
            min + offset,
            half,
            depth + 1,
            params,
            chunk,
            order,
        );
        bounds = bounds.union(&chunk.nodes[child as usize].bounds);
        children.push(child);
    }
    let node = &mut chunk.nodes[index as usize];
    node.bounds = bounds;
    node.own = own_range;
    node.subtree_end = order.len() as u32;
    node.children = children;
    index
}
