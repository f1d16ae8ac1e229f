//! Back end: glTF scenes, the JSON report, and atomic file writes.
