//! The comments slicers mark each layer with, and where a layer's block of lines starts.
//!
//! - PrusaSlicer, SuperSlicer and OrcaSlicer: `;LAYER_CHANGE`, then `;Z:<top of the layer>` and
//!   `;HEIGHT:<its thickness>`.
//! - Bambu Studio: `; CHANGE_LAYER`, then `; Z_HEIGHT: <top>` and `; LAYER_HEIGHT: <thickness>`.
//! - Cura (CuraEngine): `;LAYER:<n>`, numbered from 0 (raft layers below 0); the file's
//!   `;LAYER_COUNT:<n>` comes before the first and is no layer.
//!
//! A marker only says where the slicer starts a layer's lines; which layer it is, and its
//! height, come from the moves (a layer begins when a move extrudes at a new height, see
//! `program.rs`), so files whose slicers number layers differently read alike.

/// How a slicer marks the start of a layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LayerDialect {
    /// `;LAYER_CHANGE` (PrusaSlicer, SuperSlicer, OrcaSlicer).
    LayerChange,
    /// `; CHANGE_LAYER` (Bambu Studio).
    ChangeLayer,
    /// `;LAYER:<n>` (Cura).
    LayerNumber,
}

/// A slicer's mark of the start of a layer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerMarker {
    /// 1-based line of the marker comment.
    pub line: usize,
    /// Which slicers' marker it is.
    pub dialect: LayerDialect,
    /// The layer's number as the slicer gives it (Cura's `;LAYER:<n>`, from 0).
    pub number: Option<i64>,
    /// The top of the layer as the slicer states it (`;Z:` or `; Z_HEIGHT:`), mm.
    pub height: Option<f64>,
    /// The layer's thickness as the slicer states it (`;HEIGHT:` or `; LAYER_HEIGHT:`), mm.
    pub thickness: Option<f64>,
}

/// Where a layer of the program starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LayerStart {
    /// 1-based line before which lines run after the previous layer is printed and before
    /// anything of this one: right after the slicer's marker and the height comments that
    /// follow it, or, for a layer without a marker, the layer's first extruding move.
    pub insert_before: usize,
    /// The slicer's marker of the layer, when it wrote one since the previous layer's last
    /// extrusion.
    pub marker: Option<LayerMarker>,
}

/// What a comment line says about layers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum LayerComment {
    /// A layer starts here.
    Start(LayerDialect, Option<i64>),
    /// The top of the layer just marked, mm.
    Height(f64),
    /// The thickness of the layer just marked, mm.
    Thickness(f64),
}

/// What `comment` (the text after a line's `;`, on a line with no code) says about layers, if
/// anything.
pub(super) fn layer_comment(comment: &str) -> Option<LayerComment> {
    let trimmed = comment.trim();
    match trimmed {
        "LAYER_CHANGE" => return Some(LayerComment::Start(LayerDialect::LayerChange, None)),
        "CHANGE_LAYER" => return Some(LayerComment::Start(LayerDialect::ChangeLayer, None)),
        _ => {}
    }
    let (key, value) = trimmed.split_once(':')?;
    let number = || value.trim().parse::<f64>().ok().filter(|v| v.is_finite());
    match key.trim_end() {
        "LAYER" => {
            let layer = value.trim().parse::<i64>().ok()?;
            Some(LayerComment::Start(LayerDialect::LayerNumber, Some(layer)))
        }
        "Z" | "Z_HEIGHT" => number().map(LayerComment::Height),
        "HEIGHT" | "LAYER_HEIGHT" => number().map(LayerComment::Thickness),
        _ => None,
    }
}

/// The layer marker read last and not yet given to a layer.
#[derive(Debug, Clone, Copy)]
pub(super) struct PendingMarker {
    marker: LayerMarker,
    /// The line a layer start would be inserted before so far (the marker's next line, moved
    /// on past each height comment that directly follows).
    insert_before: usize,
}

impl PendingMarker {
    /// A marker of `dialect` (numbered `number`) on line `line`.
    pub fn new(line: usize, dialect: LayerDialect, number: Option<i64>) -> PendingMarker {
        PendingMarker {
            marker: LayerMarker {
                line,
                dialect,
                number,
                height: None,
                thickness: None,
            },
            insert_before: line + 1,
        }
    }

    /// A height comment `comment` on line `line`: taken when it directly follows the marker or
    /// its other height comments, passed over otherwise.
    pub fn follow(&mut self, line: usize, comment: LayerComment) {
        if line != self.insert_before {
            return;
        }
        match comment {
            LayerComment::Height(z) => self.marker.height = Some(z),
            LayerComment::Thickness(t) => self.marker.thickness = Some(t),
            LayerComment::Start(..) => return,
        }
        self.insert_before = line + 1;
    }

    /// The start of the layer it marks.
    pub fn start(self) -> LayerStart {
        LayerStart {
            insert_before: self.insert_before,
            marker: Some(self.marker),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_dialects_markers_and_heights_are_read() {
        use LayerComment::*;
        use LayerDialect::*;
        assert_eq!(
            layer_comment("LAYER_CHANGE"),
            Some(Start(LayerChange, None))
        );
        assert_eq!(
            layer_comment(" CHANGE_LAYER"),
            Some(Start(ChangeLayer, None))
        );
        assert_eq!(layer_comment("LAYER:0"), Some(Start(LayerNumber, Some(0))));
        assert_eq!(
            layer_comment("LAYER:-2"),
            Some(Start(LayerNumber, Some(-2)))
        );
        assert_eq!(layer_comment("Z:14.15"), Some(Height(14.15)));
        assert_eq!(layer_comment(" Z_HEIGHT: 0.2"), Some(Height(0.2)));
        assert_eq!(layer_comment("HEIGHT:0.3"), Some(Thickness(0.3)));
        assert_eq!(layer_comment(" LAYER_HEIGHT: 0.2"), Some(Thickness(0.2)));
    }

    #[test]
    fn comments_that_only_look_like_markers_are_not() {
        for comment in [
            "LAYER_COUNT:198",
            "Layer height: 0.1",
            "LAYER:",
            "LAYER:two",
            "Z:",
            "Z:nan",
            "Z:inf",
            "LAYER_CHANGE now",
            "printing object box",
            "TYPE:WALL-OUTER",
            "MESH:box.stl",
            "",
        ] {
            assert_eq!(layer_comment(comment), None, "{comment:?}");
        }
    }

    #[test]
    fn only_height_comments_right_after_the_marker_move_the_insertion() {
        let mut pending = PendingMarker::new(10, LayerDialect::LayerChange, None);
        pending.follow(11, LayerComment::Height(0.65));
        pending.follow(12, LayerComment::Thickness(0.3));
        // A height comment further on belongs to something else.
        pending.follow(14, LayerComment::Height(9.0));
        let start = pending.start();
        assert_eq!(start.insert_before, 13);
        let marker = start.marker.unwrap();
        assert_eq!(
            (marker.line, marker.height, marker.thickness),
            (10, Some(0.65), Some(0.3))
        );
        // Cura's marker stands alone: the lines go right after it.
        let start = PendingMarker::new(20, LayerDialect::LayerNumber, Some(3)).start();
        assert_eq!(start.insert_before, 21);
        assert_eq!(start.marker.unwrap().number, Some(3));
    }
}
