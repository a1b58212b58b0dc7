//! The optional vertex streams of a primitive: `TEXCOORD_1` and `COLOR_0`, each checked to
//! have one value per vertex.

use glam::{Vec2, Vec4};

use super::SceneError;

/// `TEXCOORD_1` (any glTF component type, normalized to floats) and `COLOR_0` (linear RGBA;
/// alpha 1 where the file gives RGB) of `primitive` with `vertices` positions; each empty
/// where the primitive has none. `length_error(attribute, got)` names a stream whose length
/// differs from `vertices` (an accessor whose data cannot be read counts as 0 values). The
/// accessors' types were checked by `load_checks::check_accessors` (gltf's readers assume them).
pub(super) fn read<'a, 's, F>(
    primitive: &gltf::Primitive<'a>,
    reader: &gltf::mesh::Reader<'a, 's, F>,
    vertices: usize,
    length_error: impl Fn(&str, usize) -> SceneError,
) -> Result<(Vec<Vec2>, Vec<Vec4>), SceneError>
where
    F: Clone + Fn(gltf::Buffer<'a>) -> Option<&'s [u8]>,
{
    let uvs1: Vec<Vec2> = reader
        .read_tex_coords(1)
        .map(|it| it.into_f32().map(Vec2::from).collect())
        .unwrap_or_default();
    let colors: Vec<Vec4> = reader
        .read_colors(0)
        .map(|it| it.into_rgba_f32().map(Vec4::from).collect())
        .unwrap_or_default();
    for (semantic, what, got) in [
        (gltf::Semantic::TexCoords(1), "TEXCOORD_1", uvs1.len()),
        (gltf::Semantic::Colors(0), "COLOR_0", colors.len()),
    ] {
        if primitive.get(&semantic).is_some() && got != vertices {
            return Err(length_error(what, got));
        }
    }
    Ok((uvs1, colors))
}
