//! The distances of a grid's nodes far outside the surface, computed block by block when first
//! read: the optimizer's wall constraint reads the grid inside a component and a little way out,
//! so most of these are never needed.

use std::sync::OnceLock;

use super::blocks::Blocks;
use crate::geometry::mesh::TriMesh;
use crate::geometry::tree::TriangleTree;

/// The blocks of a grid left for later, and what computes them: the same values, bit for bit,
/// as computing them with the grid.
#[derive(Debug, Clone)]
pub(super) struct Deferred {
    blocks: Blocks,
    /// The tree over the mesh, built from `mesh` on first need when the grid was read back from
    /// a cache.
    tree: OnceLock<TriangleTree>,
    mesh: Option<TriMesh>,
    /// Each block's distances once computed, in the block's node order.
    computed: Vec<OnceLock<Vec<f64>>>,
}

impl Deferred {
    /// Deferred blocks of `blocks` whose distances come from `tree`.
    pub(super) fn with_tree(blocks: Blocks, tree: TriangleTree) -> Deferred {
        Deferred {
            blocks,
            tree: OnceLock::from(tree),
            mesh: None,
            computed: (0..blocks.count()).map(|_| OnceLock::new()).collect(),
        }
    }

    /// Deferred blocks of `blocks` whose distances come from `mesh`, its tree built when the
    /// first of them is read.
    pub(super) fn with_mesh(blocks: Blocks, mesh: &TriMesh) -> Deferred {
        Deferred {
            blocks,
            tree: OnceLock::new(),
            mesh: Some(mesh.clone()),
            computed: (0..blocks.count()).map(|_| OnceLock::new()).collect(),
        }
    }

    /// The unsigned distance of the node of flat index `node`, computing its block on first use
    /// (on whichever thread asks first; the others wait for it).
    pub(super) fn distance(&self, node: usize) -> f64 {
        let b = self.blocks.of_node(node);
        let values = self.computed[b].get_or_init(|| {
            let tree = self.tree.get_or_init(|| {
                TriangleTree::new(self.mesh.as_ref().unwrap_or_else(|| {
                    unreachable!("a deferred grid holds its tree or the mesh to build it")
                }))
            });
            self.blocks.distances(tree, b, self.blocks.bound(tree, b))
        });
        values[self.blocks.position_in_block(b, node)]
    }
}
