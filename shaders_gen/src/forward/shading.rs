//! Forward shading and the G-buffer of glTF 2.0 metallic-roughness: one material of the
//! material frame (`material_frame`) among others.

/// The glTF 2.0 metallic-roughness surface (`gltf_surface`): each factor of the material's
/// record times its texture (each read through its own UV set and `KHR_texture_transform` from
/// the material atlas, with its glTF sampler's wrap and filters: `material_table`'s
/// `material_texel`), the vertex colour (`COLOR_0`) multiplying the base colour, alpha included,
/// and the normal texture in the point's tangent frame, `xy` scaled by `normal_scale`.
///
/// A library, so that an engine's own material can start from glTF's surface and change it.
#[shader_dsl::library(uses(
    crate::forward::material_surface,
    crate::shared::material_uv,
    crate::shared::material_table,
))]
pub mod gltf_material {
    /// The glTF metallic-roughness surface of `point`'s material record.
    pub fn gltf_surface(point: MaterialPoint) -> Surface {
        let m = MATERIALS[point.material];
        let d = point.uv;
        let base = m.base_color
            * material_texel(m.base_color_texture, true, m.base_color_uv, d, Vec4::ONE)
            * point.color;
        let mr = material_texel(
            m.metallic_roughness_texture,
            false,
            m.metallic_roughness_uv,
            d,
            Vec4::ONE,
        );
        let occlusion_texel =
            material_texel(m.occlusion_texture, false, m.occlusion_uv, d, Vec4::ONE).x;
        let emissive = m.emissive
            * material_texel(m.emissive_texture, true, m.emissive_uv, d, Vec4::ONE).xyz();
        let flat = Vec4::new(0.5, 0.5, 1.0, 1.0);
        let tangent_normal =
            material_texel(m.normal_texture, false, m.normal_uv, d, flat).xyz() * 2.0 - 1.0;
        let ts = Vec3::new(
            tangent_normal.x * m.normal_scale,
            tangent_normal.y * m.normal_scale,
            tangent_normal.z,
        );
        Surface {
            base_color: base,
            normal: tangent_space_normal(point, ts),
            metallic: m.metallic * mr.z,
            roughness: m.roughness * mr.y,
            occlusion: 1.0 + m.occlusion_strength * (occlusion_texel - 1.0),
            emissive,
        }
    }
}

/// Forward+ / clustered forward shading and the G-buffer of glTF PBR: the material frame
/// (`material_frame`: the light lists, decals, shadows and MSAA of every path; its axes `list`,
/// `blend` and `scalarize`) around `gltf_material`'s surface. `fs_forward` writes linear HDR
/// (`Rgba16Float`, location 0); `fs_gbuffer` the deferred paths' G-buffer. The `pbr` library's
/// `shade_light` is the BRDF (GGX distribution, Smith/Schlick-GGX geometry, Schlick Fresnel,
/// Lambert diffuse); every light with a shadow is attenuated by the `shadow_atlas` library's
/// `shadow_visibility`.
#[shader_dsl::material(
    frame = crate::forward::material_frame,
    visibility = crate::visibility::vis_frame,
    blended = crate::visibility::vis_blend,
    uses(crate::forward::gltf_material),
)]
pub mod forward {
    fn surface(point: MaterialPoint) -> Surface {
        gltf_surface(point)
    }
}
