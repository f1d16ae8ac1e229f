//! fabrication
