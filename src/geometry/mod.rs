//! Geometry: triangle meshes, loading, validation, mass properties and distance queries.
