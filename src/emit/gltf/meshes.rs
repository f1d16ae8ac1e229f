//! The meshes the glTF writer draws with, each made once and shared: components, capsules, the
//! ball, markers, the arrow and the string, and the one-primitive meshes they are written as.

use gltf::json;
use json::validation::Checked;
use nalgebra::{Point3, Vector3};

use super::paint::Paint;
use super::{f32x3, GltfError, Primitive, SharedMeshes, Writer};
use crate::emit::shapes::{self, ShapeMesh};

impl Writer<'_> {
    pub(super) fn component_mesh(
        &mut self,
        component: usize,
    ) -> Result<Option<json::Index<json::Mesh>>, GltfError> {
        if let Some(mesh) = self.meshes.components[component] {
            return Ok(Some(mesh));
        }
        let c = &self.model.components[component];
        if c.triangles.is_empty() {
            return Ok(None);
        }
        let positions: Vec<Point3<f64>> = c
            .positions
            .iter()
            .map(|p| Point3::from(p.coords * self.metres))
            .collect();
        let mesh = self.mesh(
            &c.name,
            Primitive {
                positions: &positions,
                normals: &[],
                indices: c.triangles.iter().flatten().copied().collect(),
                paint: Paint::Component,
            },
        )?;
        self.meshes.components[component] = Some(mesh);
        Ok(Some(mesh))
    }

    pub(super) fn capsule_mesh(
        &mut self,
        capsule: usize,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        if self.meshes.capsules.is_empty() {
            // All capsule meshes at once, in model order, so indices do not depend on pose order.
            let m = self.metres;
            for c in &self.model.capsules {
                let (from, to) = (
                    Point3::from(c.from.coords * m),
                    Point3::from(c.to.coords * m),
                );
                let shape = shapes::capsule(&from, &to, c.radius * m);
                let mesh =
                    self.shape_mesh(&format!("capsule {}", c.name), &shape, Paint::Capsule)?;
                self.meshes.capsules.push(mesh);
            }
        }
        Ok(self.meshes.capsules[capsule])
    }

    /// The mesh in the cache slot `slot`, built by `build` the first time it is asked for.
    pub(super) fn cached(
        &mut self,
        slot: fn(&mut SharedMeshes) -> &mut Option<json::Index<json::Mesh>>,
        build: impl FnOnce(&mut Self) -> Result<json::Index<json::Mesh>, GltfError>,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        if let Some(mesh) = *slot(&mut self.meshes) {
            return Ok(mesh);
        }
        let mesh = build(self)?;
        *slot(&mut self.meshes) = Some(mesh);
        Ok(mesh)
    }

    pub(super) fn ball_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.ball,
            |writer| writer.shape_mesh("ball", &shapes::unit_sphere(), Paint::Steel),
        )
    }

    pub(super) fn centre_of_mass_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.centre_of_mass,
            |writer| {
                let shape = shapes::unit_octahedron();
                writer.shape_mesh("centre of mass marker", &shape, Paint::CentreOfMass)
            },
        )
    }

    pub(super) fn buoyancy_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.buoyancy,
            |writer| {
                let shape = shapes::unit_octahedron();
                writer.shape_mesh("buoyancy centre marker", &shape, Paint::Buoyancy)
            },
        )
    }

    pub(super) fn gravity_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.gravity,
            |writer| {
                let arrow = shapes::unit_arrow(&-Vector3::y());
                writer.shape_mesh("gravity arrow", &arrow, Paint::Gravity)
            },
        )
    }

    pub(super) fn string_mesh(&mut self) -> Result<json::Index<json::Mesh>, GltfError> {
        self.cached(
            |meshes| &mut meshes.string,
            |writer| {
                // Scaled by the arrow length at the node: the radius is relative to it.
                let tube =
                    shapes::unit_line(&Vector3::y(), writer.line_radius / writer.arrow_length);
                writer.shape_mesh("string", &tube, Paint::String)
            },
        )
    }

    pub(super) fn shape_mesh(
        &mut self,
        name: &str,
        shape: &ShapeMesh,
        paint: Paint,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        self.mesh(
            name,
            Primitive {
                positions: &shape.positions,
                normals: &shape.normals,
                indices: shape.triangles.iter().flatten().copied().collect(),
                paint,
            },
        )
    }

    /// A one-primitive mesh; its data goes into the buffer.
    pub(super) fn mesh(
        &mut self,
        name: &str,
        primitive: Primitive<'_>,
    ) -> Result<json::Index<json::Mesh>, GltfError> {
        let positions = primitive
            .positions
            .iter()
            .enumerate()
            .map(|(i, p)| f32x3(&p.coords, || format!("vertex {i} of mesh `{name}`")))
            .collect::<Result<Vec<_>, _>>()?;
        let mut attributes = std::collections::BTreeMap::new();
        let position_accessor = self.vec3_accessor(&positions, true);
        attributes.insert(
            Checked::Valid(json::mesh::Semantic::Positions),
            position_accessor,
        );
        if !primitive.normals.is_empty() {
            let normals: Vec<[f32; 3]> = primitive
                .normals
                .iter()
                .map(|n| {
                    let n = n.normalize().cast::<f32>();
                    let n = n / n.norm();
                    [n.x, n.y, n.z]
                })
                .collect();
            let normal_accessor = self.vec3_accessor(&normals, false);
            attributes.insert(
                Checked::Valid(json::mesh::Semantic::Normals),
                normal_accessor,
            );
        }
        let indices = Some(self.index_accessor(&primitive.indices));
        let material = self.material(primitive.paint);
        let mesh = json::Mesh {
            extensions: None,
            extras: None,
            name: Some(name.to_owned()),
            primitives: vec![json::mesh::Primitive {
                attributes,
                extensions: None,
                extras: None,
                indices,
                material: Some(material),
                mode: Checked::Valid(json::mesh::Mode::Triangles),
                targets: None,
            }],
            weights: None,
        };
        Ok(self.root.push(mesh))
    }

    pub(super) fn material(&mut self, paint: Paint) -> json::Index<json::Material> {
        let slot = Paint::ALL
            .iter()
            .position(|&p| p == paint)
            .expect("every paint is listed");
        if let Some(index) = self.materials[slot] {
            return index;
        }
        let index = self.root.push(paint.material());
        self.materials[slot] = Some(index);
        index
    }
}
