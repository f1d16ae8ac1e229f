//! The front end: the project-file grammar and the typed project it describes.

pub mod model;
pub mod vocabulary;
