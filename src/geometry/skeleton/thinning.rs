//! Topology-preserving thinning of a voxel set to curves one voxel wide.
//!
//! Directional sequential thinning after Lee, Kashyap and Chu (1994): each pass visits the six
//! face directions in a fixed order; for each, the border voxels on that side (empty neighbour in
//! that direction) that are simple and not the end of a curve are collected, then removed in
//! eight subfields (by the parity of their indices) if they still are. Passes repeat until nothing changes. Objects are
//! 26-connected, the background 6-connected.

use crate::cancel::Cancel;

/// Neighbourhood position `(dx + 1) + 3 (dy + 1) + 9 (dz + 1)` of the voxel itself.
const CENTRE: usize = 13;

/// Bit masks over the 27 positions of a 3×3×3 neighbourhood.
struct Tables {
    /// Per position, the positions 26-adjacent to it (centre excluded).
    adjacent26: [u32; 27],
    /// Per position, the positions 6-adjacent to it among the 18-neighbourhood.
    adjacent6: [u32; 27],
    /// The 18-neighbourhood (faces and edges) without the centre.
    n18: u32,
    /// The six face neighbours of the centre.
    faces: u32,
}

fn position_offset(p: usize) -> [i32; 3] {
    [
        (p % 3) as i32 - 1,
        ((p / 3) % 3) as i32 - 1,
        (p / 9) as i32 - 1,
    ]
}

impl Tables {
    fn new() -> Tables {
        let nonzero = |o: [i32; 3]| o.iter().filter(|&&c| c != 0).count();
        let n18 = (0..27)
            .filter(|&p| p != CENTRE && nonzero(position_offset(p)) <= 2)
            .fold(0u32, |m, p| m | 1 << p);
        let faces = (0..27)
            .filter(|&p| nonzero(position_offset(p)) == 1)
            .fold(0u32, |m, p| m | 1 << p);
        let mut adjacent26 = [0u32; 27];
        let mut adjacent6 = [0u32; 27];
        for p in 0..27 {
            let a = position_offset(p);
            for q in 0..27 {
                if q == p || q == CENTRE {
                    continue;
                }
                let b = position_offset(q);
                let d = [0, 1, 2].map(|i| (a[i] - b[i]).abs());
                if d.iter().all(|&c| c <= 1) {
                    adjacent26[p] |= 1 << q;
                    if d.iter().sum::<i32>() == 1 && n18 & (1 << q) != 0 {
                        adjacent6[p] |= 1 << q;
                    }
                }
            }
        }
        Tables {
            adjacent26,
            adjacent6,
            n18,
            faces,
        }
    }

    /// Whether removing the centre of neighbourhood `mask` keeps the topology: one 26-component
    /// of object voxels around it, and one 6-component of background in its 18-neighbourhood
    /// that touches one of its faces (Bertrand and Malandain 1994).
    fn is_simple(&self, mask: u32) -> bool {
        let object = mask & !(1 << CENTRE) & ((1 << 27) - 1);
        let background = !mask & self.n18;
        components(object, &self.adjacent26, object) == 1
            && components(background, &self.adjacent6, self.faces) == 1
    }
}

/// The number (0, 1 or 2 meaning "more than one") of components of `set` under `adjacent`
/// that contain a position of `seeds`.
fn components(set: u32, adjacent: &[u32; 27], seeds: u32) -> u32 {
    let mut remaining = set;
    let mut count = 0;
    while remaining & seeds != 0 {
        let start = (remaining & seeds).trailing_zeros();
        let mut component = 1u32 << start;
        let mut frontier = component;
        while frontier != 0 {
            let b = frontier.trailing_zeros() as usize;
            frontier &= frontier - 1;
            let new = adjacent[b] & remaining & !component;
            component |= new;
            frontier |= new;
        }
        remaining &= !component;
        count += 1;
        if count > 1 {
            break;
        }
    }
    count
}

/// Thins `occupied` (one flag per node of a grid of `dims`, x fastest) in place to curves one
/// voxel wide with the same topology. Voxels on the grid's outer layer are cleared first, so
/// every neighbourhood lies inside the grid.
///
/// `depth[v]` orders the removal (distance ordering, Pudney 1998): voxels are eligible only once
/// their depth is at most a threshold that rises by `step` from the shallowest voxel, and at each
/// threshold the directional passes run until nothing changes. Curves therefore form where the
/// solid is deepest, and a bump on the surface cannot start a spur. Pass equal depths for plain
/// directional thinning.
///
/// Gives up, returning `false` with `occupied` half thinned, soon after `cancel` is set.
pub(super) fn thin(
    dims: [usize; 3],
    occupied: &mut [bool],
    depth: &[f64],
    step: f64,
    cancel: &Cancel,
) -> bool {
    let [nx, ny, nz] = dims;
    let sizes_agree = occupied.len() == nx * ny * nz && depth.len() == occupied.len();
    if nx < 3 || ny < 3 || nz < 3 || !sizes_agree || step.is_nan() || step <= 0.0 {
        occupied.iter_mut().for_each(|o| *o = false);
        return true;
    }
    let mut live: Vec<usize> = Vec::new();
    for (index, o) in occupied.iter_mut().enumerate() {
        let (i, j, k) = (index % nx, (index / nx) % ny, index / (nx * ny));
        let interior = i > 0 && j > 0 && k > 0 && i + 1 < nx && j + 1 < ny && k + 1 < nz;
        if !interior {
            *o = false;
        } else if *o {
            live.push(index);
        }
    }
    let tables = Tables::new();
    let offsets: [isize; 27] = std::array::from_fn(|p| {
        let [dx, dy, dz] = position_offset(p);
        dx as isize + nx as isize * (dy as isize + ny as isize * dz as isize)
    });
    // Face neighbours in the order the passes visit them: +z, −z, +y, −y, +x, −x.
    let directions = [22, 4, 16, 10, 14, 12];
    let mask_at = |occupied: &[bool], v: usize| -> u32 {
        offsets.iter().enumerate().fold(0u32, |m, (p, &o)| {
            if occupied[v.wrapping_add_signed(o)] {
                m | 1 << p
            } else {
                m
            }
        })
    };
    let subfield = |v: usize| (v % nx) % 2 + 2 * ((v / nx) % ny % 2) + 4 * (v / (nx * ny) % 2);
    let is_end = |mask: u32| (mask & !(1 << CENTRE)).count_ones() == 1;
    let mut candidates = Vec::new();
    // Directional passes over the voxels of `live` until nothing changes; `live` keeps the
    // ones left.
    let mut passes = |live: &mut Vec<usize>, occupied: &mut [bool]| loop {
        let mut changed = false;
        for &direction in &directions {
            candidates.clear();
            // Candidates are judged on the object as it was at the start of the subiteration,
            // so erosion cannot run along a scan line within one subiteration.
            candidates.extend(live.iter().copied().filter(|&v| {
                occupied[v] && !occupied[v.wrapping_add_signed(offsets[direction])] && {
                    let mask = mask_at(occupied, v);
                    !is_end(mask) && tables.is_simple(mask)
                }
            }));
            // Eight subfields by the parity of (i, j, k): no two voxels of one subfield are
            // neighbours, so removing them one by one is the same as removing them at once, and
            // an end cannot recede along a curve within one subfield.
            for parity in 0..8 {
                for &v in candidates.iter().filter(|&&v| subfield(v) == parity) {
                    let mask = mask_at(occupied, v);
                    if !is_end(mask) && tables.is_simple(mask) {
                        occupied[v] = false;
                        changed = true;
                    }
                }
            }
        }
        live.retain(|&v| occupied[v]);
        if !changed {
            break;
        }
    };
    // Voxels by depth (then index); the first `eligible` of them are below the threshold.
    let mut order = live.clone();
    order.sort_by(|&a, &b| depth[a].total_cmp(&depth[b]).then(a.cmp(&b)));
    let Some(&first) = order.first() else {
        return true;
    };
    let mut threshold = depth[first];
    let mut eligible = 0;
    live.clear();
    while eligible < order.len() {
        if cancel.is_cancelled() {
            return false;
        }
        while eligible < order.len() && depth[order[eligible]] <= threshold {
            live.push(order[eligible]);
            eligible += 1;
        }
        live.sort_unstable();
        passes(&mut live, occupied);
        threshold += step;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mask_of(points: &[[i32; 3]]) -> u32 {
        points.iter().fold(1 << CENTRE, |m, o| {
            m | 1 << ((o[0] + 1) + 3 * (o[1] + 1) + 9 * (o[2] + 1))
        })
    }

    #[test]
    fn simple_points() {
        let t = Tables::new();
        // Interior of a curve: removing it disconnects.
        assert!(!t.is_simple(mask_of(&[[-1, 0, 0], [1, 0, 0]])));
        // The end of a curve, or a corner of a solid block, is simple.
        assert!(t.is_simple(mask_of(&[[1, 0, 0]])));
        let block: Vec<[i32; 3]> = (0..27)
            .map(position_offset)
            .filter(|o| o.iter().all(|&c| c >= 0) && *o != [0, 0, 0])
            .collect();
        assert!(t.is_simple(mask_of(&block)));
        // An isolated voxel, and the centre of a full block (it would make a cavity), are not.
        assert!(!t.is_simple(mask_of(&[])));
        let full: Vec<[i32; 3]> = (0..27).map(position_offset).collect();
        assert!(!t.is_simple(mask_of(&full)));
        // A voxel closing a ring of neighbours in a plane: removing it opens a tunnel.
        let ring: Vec<[i32; 3]> = (0..27)
            .map(position_offset)
            .filter(|o| o[2] == 0 && *o != [0, 0, 0])
            .collect();
        assert!(!t.is_simple(mask_of(&ring)));
    }

    #[test]
    fn a_bar_thins_to_a_line() {
        let dims = [20, 9, 9];
        let mut occupied = vec![false; 20 * 81];
        let depth = vec![0.0; 20 * 81];
        for k in 2..7 {
            for j in 2..7 {
                for i in 2..18 {
                    occupied[i + 20 * (j + 9 * k)] = true;
                }
            }
        }
        assert!(thin(dims, &mut occupied, &depth, 1.0, &Cancel::new()));
        let left: Vec<usize> = (0..occupied.len()).filter(|&v| occupied[v]).collect();
        assert!(left.len() >= 8, "{}", left.len());
        // Every voxel left has at most two neighbours along the bar away from its ends.
        for &v in &left {
            let (j, k) = ((v / 20) % 9, v / 180);
            assert!((3..=5).contains(&j) && (3..=5).contains(&k), "{v}");
        }
    }

    #[test]
    fn a_round_rod_thins_to_a_line_along_it() {
        let dims = [20, 20, 80];
        let mut occupied = vec![false; 20 * 20 * 80];
        let mut depth = vec![0.0; 20 * 20 * 80];
        for k in 5..75 {
            for j in 0..20 {
                for i in 0..20 {
                    let (x, y) = (i as f64 - 9.7, j as f64 - 9.6);
                    occupied[i + 20 * (j + 20 * k)] = x * x + y * y < 5.3 * 5.3;
                    depth[i + 20 * (j + 20 * k)] = (5.3 - (x * x + y * y).sqrt()).min(5.0);
                }
            }
        }
        assert!(thin(dims, &mut occupied, &depth, 1.0, &Cancel::new()));
        let left: Vec<[usize; 3]> = (0..occupied.len())
            .filter(|&v| occupied[v])
            .map(|v| [v % 20, (v / 20) % 20, v / 400])
            .collect();
        // One voxel per layer over most of the rod, near its axis.
        assert!(left.len() > 50, "{left:?}");
        for k in 15..65 {
            let layer: Vec<_> = left.iter().filter(|v| v[2] == k).collect();
            assert_eq!(layer.len(), 1, "layer {k}: {layer:?}");
            assert!(layer[0][0].abs_diff(10) <= 1 && layer[0][1].abs_diff(10) <= 1);
        }
    }
}
