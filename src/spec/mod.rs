//! Front end: KDL project text to a typed, span-carrying project.

pub mod vocabulary;
