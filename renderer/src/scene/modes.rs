//! Primitive modes. The renderer draws triangle lists; glTF's triangle strips and fans become
//! lists at load, keeping the winding the glTF 2.0 specification gives them (section 3.7.2.1,
//! "Topology Types"). Points and lines are not drawn: the loader skips them with a
//! [`super::SceneWarning::SkippedPrimitive`], and [`undrawn`] names them.

use gltf::mesh::Mode;

/// The glTF name of `mode` when the renderer does not draw it (points and lines); `None` for
/// the triangle modes.
pub(super) fn undrawn(mode: Mode) -> Option<&'static str> {
    match mode {
        Mode::Points => Some("POINTS"),
        Mode::Lines => Some("LINES"),
        Mode::LineLoop => Some("LINE_LOOP"),
        Mode::LineStrip => Some("LINE_STRIP"),
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan => None,
    }
}

/// `vertices` (the primitive's indices, or `0..n` when it has none) in `mode`, as a triangle
/// list. A strip or fan of fewer than 3 vertices has no triangle. A mode [`undrawn`] names
/// gives no triangle either.
pub(super) fn triangle_list(mode: Mode, vertices: Vec<u32>) -> Vec<u32> {
    match mode {
        Mode::Triangles => vertices,
        Mode::TriangleStrip => strip(&vertices),
        Mode::TriangleFan => fan(&vertices),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => Vec::new(),
    }
}

/// Triangle `i` of a strip is `{v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]}`: every other
/// triangle swaps its last two vertices, so all keep the first one's winding.
fn strip(v: &[u32]) -> Vec<u32> {
    v.windows(3)
        .enumerate()
        .flat_map(|(i, w)| {
            if i % 2 == 0 {
                [w[0], w[1], w[2]]
            } else {
                [w[0], w[2], w[1]]
            }
        })
        .collect()
}

/// Triangle `i` of a fan is `{v[i + 1], v[i + 2], v[0]}`.
fn fan(v: &[u32]) -> Vec<u32> {
    let Some((&hub, rim)) = v.split_first() else {
        return Vec::new();
    };
    rim.windows(2).flat_map(|w| [w[0], w[1], hub]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_alternate_and_fans_turn_around_the_first_vertex() {
        assert_eq!(
            triangle_list(Mode::TriangleStrip, vec![10, 11, 12, 13, 14, 15]),
            [10, 11, 12, 11, 13, 12, 12, 13, 14, 13, 15, 14]
        );
        assert_eq!(
            triangle_list(Mode::TriangleFan, vec![10, 11, 12, 13]),
            [11, 12, 10, 12, 13, 10]
        );
        assert_eq!(triangle_list(Mode::Triangles, vec![3, 1, 2]), [3, 1, 2]);
    }

    #[test]
    fn fewer_than_three_vertices_make_no_triangle() {
        for mode in [Mode::TriangleStrip, Mode::TriangleFan] {
            for short in [vec![], vec![4], vec![4, 5]] {
                assert_eq!(triangle_list(mode, short), [] as [u32; 0], "{mode:?}");
            }
            assert_eq!(triangle_list(mode, vec![4, 5, 6]).len(), 3, "{mode:?}");
        }
    }

    #[test]
    fn only_points_and_lines_are_undrawn() {
        assert_eq!(
            [
                Mode::Points,
                Mode::Lines,
                Mode::LineLoop,
                Mode::LineStrip,
                Mode::Triangles,
                Mode::TriangleStrip,
                Mode::TriangleFan
            ]
            .map(undrawn),
            [
                Some("POINTS"),
                Some("LINES"),
                Some("LINE_LOOP"),
                Some("LINE_STRIP"),
                None,
                None,
                None
            ]
        );
        assert_eq!(triangle_list(Mode::Lines, vec![0, 1, 2]), [] as [u32; 0]);
    }
}
