//! The graph of a thinned voxel skeleton: junctions, ends and the branches between them, with
//! spurs pruned and short links between junctions contracted.

use nalgebra::Point3;

/// Voxel centre and radius lookup for the graph; implemented over a `DistanceGrid`.
pub(super) trait Field {
    /// Centre of voxel `index` (flat, x fastest).
    fn position(&self, index: usize) -> Point3<f64>;
    /// Inscribed radius at `p` (positive inside, clamped at 0).
    fn radius(&self, p: &Point3<f64>) -> f64;
}

/// A junction, an end, or a point chosen on a closed loop.
#[derive(Debug, Clone)]
struct Node {
    position: Point3<f64>,
    radius: f64,
    alive: bool,
}

/// A chain of voxels between two nodes (possibly the same node), as points from `ends[0]` to
/// `ends[1]`, the nodes' own positions first and last.
#[derive(Debug, Clone)]
pub(super) struct Branch {
    ends: [usize; 2],
    pub(super) points: Vec<Point3<f64>>,
    alive: bool,
}

impl Branch {
    fn length(&self) -> f64 {
        self.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }
}

/// How much of the graph is pruned; all ratios to the inscribed radius at a junction.
#[derive(Debug, Clone, Copy)]
pub(super) struct Pruning {
    /// An end branch is a spur when the distance from its junction to its end is below this
    /// times the larger inscribed radius of the two.
    pub spur: f64,
    /// A branch between two junctions shorter than this times the larger of their radii is
    /// contracted to a point.
    pub contract: f64,
    /// A loop from a node back to itself shorter than this times its radius is removed.
    pub loop_length: f64,
}

/// The skeleton graph of a voxel set.
pub(super) struct Graph {
    nodes: Vec<Node>,
    branches: Vec<Branch>,
}

impl Graph {
    /// Builds the graph of the occupied voxels (26-adjacency) of a grid of `dims`. Occupied
    /// voxels must not lie on the grid's outer layer.
    pub(super) fn new(dims: [usize; 3], occupied: &[bool], field: &impl Field) -> Graph {
        let [nx, ny, _] = dims;
        let offsets: Vec<isize> = (0..27)
            .filter(|&p| p != 13)
            .map(|p| {
                let (dx, dy, dz) = (p % 3, (p / 3) % 3, p / 9);
                (dx as isize - 1)
                    + nx as isize * ((dy as isize - 1) + ny as isize * (dz as isize - 1))
            })
            .collect();
        let neighbours = |v: usize| -> Vec<usize> {
            offsets
                .iter()
                .map(|&o| v.wrapping_add_signed(o))
                .filter(|&w| occupied[w])
                .collect()
        };
        let voxels: Vec<usize> = (0..occupied.len()).filter(|&v| occupied[v]).collect();
        const NONE: u32 = u32::MAX;
        let mut node_of = vec![NONE; occupied.len()];
        let mut degree = vec![0u8; occupied.len()];
        for &v in &voxels {
            degree[v] = neighbours(v).len() as u8;
        }
        let mut graph = Graph {
            nodes: Vec::new(),
            branches: Vec::new(),
        };
        let mut members: Vec<Vec<usize>> = Vec::new();
        // Junction clusters (26-connected voxels with three or more neighbours) and ends.
        for &v in &voxels {
            if node_of[v] != NONE || degree[v] == 2 || degree[v] == 0 {
                continue;
            }
            let id = graph.nodes.len() as u32;
            let mut cluster = vec![v];
            node_of[v] = id;
            if degree[v] >= 3 {
                let mut next = 0;
                while next < cluster.len() {
                    for w in neighbours(cluster[next]) {
                        if degree[w] >= 3 && node_of[w] == NONE {
                            node_of[w] = id;
                            cluster.push(w);
                        }
                    }
                    next += 1;
                }
                cluster.sort_unstable();
            }
            let sum = cluster.iter().fold(Point3::origin().coords, |s, &w| {
                s + field.position(w).coords
            });
            let position = Point3::from(sum / cluster.len() as f64);
            graph.push_node(position, field);
            members.push(cluster);
        }
        // Branches from every node.
        let mut visited = vec![false; occupied.len()];
        let mut direct = Vec::new();
        for (id, cluster) in members.iter().enumerate() {
            for &u in cluster {
                for w in neighbours(u) {
                    let other = node_of[w];
                    if other == id as u32 {
                        continue;
                    }
                    if other != NONE {
                        let pair = (id.min(other as usize), id.max(other as usize));
                        if !direct.contains(&pair) {
                            direct.push(pair);
                            let points =
                                vec![graph.nodes[pair.0].position, graph.nodes[pair.1].position];
                            graph.push_branch([pair.0, pair.1], points);
                        }
                        continue;
                    }
                    if visited[w] {
                        continue;
                    }
                    let mut points = vec![graph.nodes[id].position];
                    let (mut previous, mut current) = (u, w);
                    let end = loop {
                        visited[current] = true;
                        points.push(field.position(current));
                        let next = neighbours(current).into_iter().find(|&n| n != previous);
                        match next {
                            Some(n) if node_of[n] != NONE => break Some(node_of[n] as usize),
                            Some(n) if !visited[n] => (previous, current) = (current, n),
                            _ => break None,
                        }
                    };
                    let end = end.unwrap_or(id);
                    points.push(graph.nodes[end].position);
                    graph.push_branch([id, end], points);
                }
            }
        }
        // Closed loops without a junction: a node on the lowest voxel of each.
        for &v in &voxels {
            if visited[v] || degree[v] != 2 || node_of[v] != NONE {
                continue;
            }
            let id = graph.nodes.len();
            graph.push_node(field.position(v), field);
            node_of[v] = id as u32;
            let mut points = vec![field.position(v)];
            let mut previous = v;
            let mut current = neighbours(v)[0];
            while current != v && !visited[current] {
                visited[current] = true;
                points.push(field.position(current));
                match neighbours(current).into_iter().find(|&n| n != previous) {
                    Some(n) => (previous, current) = (current, n),
                    None => break,
                }
            }
            points.push(field.position(v));
            graph.push_branch([id, id], points);
        }
        graph
    }

    fn push_node(&mut self, position: Point3<f64>, field: &impl Field) {
        self.nodes.push(Node {
            position,
            radius: field.radius(&position),
            alive: true,
        });
    }

    fn push_branch(&mut self, ends: [usize; 2], points: Vec<Point3<f64>>) {
        self.branches.push(Branch {
            ends,
            points,
            alive: true,
        });
    }

    /// Number of branch ends at every node (a loop counts twice).
    fn degrees(&self) -> Vec<usize> {
        let mut degrees = vec![0; self.nodes.len()];
        for branch in self.branches.iter().filter(|b| b.alive) {
            for &end in &branch.ends {
                degrees[end] += 1;
            }
        }
        degrees
    }

    /// Prunes spurs, contracts short links and removes short loops, one at a time (the
    /// smallest first), merging branches through nodes left with two, until none is left.
    pub(super) fn prune(&mut self, pruning: &Pruning) {
        self.dissolve();
        loop {
            let degrees = self.degrees();
            // (score, branch, kind): kind 0 spur, 1 contraction, 2 loop.
            let mut best: Option<(f64, usize, u8)> = None;
            let mut consider = |score: f64, b: usize, kind: u8| {
                if best.is_none_or(|(s, _, _)| score < s) {
                    best = Some((score, b, kind));
                }
            };
            for (b, branch) in self.branches.iter().enumerate().filter(|(_, b)| b.alive) {
                let [a, z] = branch.ends;
                if a == z {
                    let score = branch.length() / self.nodes[a].radius.max(f64::MIN_POSITIVE);
                    if degrees[a] > 2 && score < pruning.loop_length {
                        consider(score / pruning.loop_length, b, 2);
                    }
                    continue;
                }
                let (da, dz) = (degrees[a], degrees[z]);
                if (da == 1) != (dz == 1) && da.max(dz) >= 3 {
                    let (end, junction) = if da == 1 { (a, z) } else { (z, a) };
                    let (e, j) = (&self.nodes[end], &self.nodes[junction]);
                    let reach = (e.position - j.position).norm();
                    let score = reach / j.radius.max(e.radius).max(f64::MIN_POSITIVE);
                    if score < pruning.spur {
                        consider(score / pruning.spur, b, 0);
                    }
                } else if da >= 3 && dz >= 3 {
                    let r = self.nodes[a].radius.max(self.nodes[z].radius);
                    let score = branch.length() / r.max(f64::MIN_POSITIVE);
                    if score < pruning.contract {
                        consider(score / pruning.contract, b, 1);
                    }
                }
            }
            let Some((_, b, kind)) = best else { break };
            self.branches[b].alive = false;
            if kind == 0 {
                let [a, z] = self.branches[b].ends;
                let end = if degrees[a] == 1 { a } else { z };
                self.nodes[end].alive = false;
            } else if kind == 1 {
                self.contract(b);
            }
            self.dissolve();
        }
    }

    /// Merges the far node of link `b` into its near node, placed at whichever of the two is
    /// deeper inside.
    fn contract(&mut self, b: usize) {
        let [keep, gone] = self.branches[b].ends;
        if self.nodes[gone].radius > self.nodes[keep].radius {
            self.nodes[keep].position = self.nodes[gone].position;
            self.nodes[keep].radius = self.nodes[gone].radius;
        }
        self.nodes[gone].alive = false;
        let position = self.nodes[keep].position;
        for branch in self.branches.iter_mut().filter(|b| b.alive) {
            for side in 0..2 {
                if branch.ends[side] == gone {
                    branch.ends[side] = keep;
                }
                if branch.ends[side] == keep {
                    let last = branch.points.len() - 1;
                    branch.points[if side == 0 { 0 } else { last }] = position;
                }
            }
        }
    }

    /// Joins the two branches through every node with exactly two distinct branch ends.
    fn dissolve(&mut self) {
        let mut incident: Vec<Vec<usize>> = vec![Vec::new(); self.nodes.len()];
        for (b, branch) in self.branches.iter().enumerate().filter(|(_, b)| b.alive) {
            incident[branch.ends[0]].push(b);
            if branch.ends[1] != branch.ends[0] {
                incident[branch.ends[1]].push(b);
            }
        }
        for n in 0..self.nodes.len() {
            if !self.nodes[n].alive {
                continue;
            }
            let [first, second] = incident[n][..] else {
                continue;
            };
            let ends = |b: usize| self.branches[b].ends;
            if ends(first)[0] == ends(first)[1] || ends(second)[0] == ends(second)[1] {
                continue;
            }
            let mut head = self.branches[first].clone();
            if head.ends[1] != n {
                head.ends.reverse();
                head.points.reverse();
            }
            let mut tail = self.branches[second].clone();
            if tail.ends[0] != n {
                tail.ends.reverse();
                tail.points.reverse();
            }
            head.points.extend_from_slice(&tail.points[1..]);
            head.ends[1] = tail.ends[1];
            // The far node of the second branch now meets the first instead.
            let far = tail.ends[1];
            for slot in incident[far].iter_mut() {
                if *slot == second {
                    *slot = first;
                }
            }
            incident[far].dedup();
            self.branches[first] = head;
            self.branches[second].alive = false;
            self.nodes[n].alive = false;
        }
    }

    /// The branches left, in the order they were found.
    pub(super) fn branches(&self) -> impl Iterator<Item = &Branch> {
        self.branches.iter().filter(|b| b.alive)
    }
}
