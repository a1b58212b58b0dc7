//! `#[material]`: a module with a `surface` function expanded into a `#[shader]` module of a
//! material frame (here a small frame of the test's own, with the frame contract's names), as
//! tools see it through `shader_modules`, and the expansion's refusals at the author's spans.

const FRAME: &str = r#"
#[library(axes(list: u32 = [0, 1, 2], blend: bool = [false, true], scalarize: bool = [false, true]))]
pub mod mini_frame {
    pub struct VsOut {
        #[builtin(position)]
        pub clip: Vec4,
        #[location(0)]
        pub world: Vec3,
    }
    pub struct GBufferOut {
        #[location(0)]
        pub albedo: Vec4,
    }
    pub struct MaterialPoint { pub world: Vec3, pub params: u32 }
    pub struct Surface { pub base_color: Vec4 }
    pub fn material_vertex(position: Vec3, normal: Vec3, uv: Vec2, tangent: Vec4, uv1: Vec2, color: Vec4, draw_index: u32) -> VsOut {
        VsOut { clip: position.extend(1.0), world: position + normal * (draw_index as f32) }
    }
    pub fn forward_facing(input: VsOut, front: bool) -> bool {
        front || blend
    }
    pub struct FragmentDerivatives { pub p_dx: Vec3 }
    pub fn fragment_derivatives(input: VsOut) -> FragmentDerivatives {
        FragmentDerivatives { p_dx: dpdx(input.world) }
    }
    pub fn material_point(input: VsOut, front: bool) -> MaterialPoint {
        MaterialPoint { world: input.world, params: select(front, 1u32, 0u32) }
    }
    pub fn material_point_from(input: VsOut, front: bool, d: FragmentDerivatives) -> MaterialPoint {
        MaterialPoint { world: input.world + d.p_dx, params: select(front, 1u32, 0u32) }
    }
    pub fn material_forward(input: VsOut, point: MaterialPoint, s: Surface) -> Vec4 {
        s.base_color * ((list + 1u32) as f32)
    }
    pub fn material_forward_from(input: VsOut, point: MaterialPoint, s: Surface, d: FragmentDerivatives) -> Vec4 {
        s.base_color * d.p_dx.x
    }
    pub fn material_gbuffer(input: VsOut, point: MaterialPoint, s: Surface) -> GBufferOut {
        GBufferOut { albedo: s.base_color }
    }
}
"#;

/// A small visibility frame with the contract's names: what the kernel `vis_shade` calls.
const VIS_FRAME: &str = r#"
#[library(axes(list: u32 = [0, 1, 2], blend: bool = [false, true], scalarize: bool = [false, true], msaa: u32 = [0, 1, 2, 4, 8]), uses(crate::mini_frame))]
pub mod mini_vis {
    pub struct SceneTriangle { pub draw: u32 }
    pub struct VisPoint { pub point: MaterialPoint }
    #[storage(group = 0, binding = 18, read_write)]
    #[when(msaa > 0 && !blend)]
    static SUMS: [Vec4];
    pub fn vis_on_screen(p: UVec2) -> bool {
        p.x < 64u32
    }
    pub fn vis_begin(p: UVec2) -> Vec3 {
        Vec3::ZERO
    }
    pub fn vis_id_at(p: UVec2, s: u32) -> u32 {
        p.x + s
    }
    pub fn vis_all_samples() -> u32 {
        1u32
    }
    pub fn vis_samples_of(p: UVec2, id: u32, left: u32) -> u32 {
        left
    }
    pub fn vis_triangle(id: u32) -> SceneTriangle {
        SceneTriangle { draw: id - 1u32 }
    }
    pub fn vis_shades(tri: SceneTriangle) -> bool {
        tri.draw > 2u32
    }
    pub fn vis_point(tri: SceneTriangle, p: UVec2) -> VisPoint {
        VisPoint { point: MaterialPoint { world: Vec3::splat(tri.draw as f32), params: p.y } }
    }
    pub fn vis_radiance(v: VisPoint, s: Surface) -> Vec3 {
        s.base_color.xyz() * v.point.world
    }
    pub fn vis_finish(p: UVec2, total: Vec3, kinds: u32) {
        if msaa > 0 && !blend {
            SUMS[p.x] = total.extend(kinds as f32);
        }
    }
}
"#;

/// A small frame of the blended surfaces over the compute rasteriser's samples with the
/// contract's names: what `vs_blend`, `fs_blend_list`, `vis_blend_args`, `vis_shade_blended`,
/// `fs_blend_listed` and `fs_forward_vis64` call.
const BLEND_FRAME: &str = r#"
#[library(axes(list: u32 = [0, 1, 2], blend: bool = [false, true], scalarize: bool = [false, true], msaa: u32 = [0, 1, 2, 4, 8]), uses(crate::mini_frame, crate::mini_vis))]
pub mod mini_blend {
    pub struct VisBlendVsOut {
        #[builtin(position)]
        pub clip: Vec4,
        #[location(0)]
        pub world: Vec3,
        #[location(1)]
        #[interpolate(flat)]
        pub id: u32,
    }
    pub struct VisBlendOut {
        #[location(0)]
        pub color: Vec4,
        #[builtin(sample_mask)]
        pub mask: u32,
    }
    pub struct BlendRecord { pub next: u32, pub id: u32, pub pixel: UVec2 }
    #[storage(group = 0, binding = 17, read_write)]
    #[when(msaa > 0 && blend)]
    static RECORDS: [Vec4];
    pub fn vis_blend_vertex(index: u32, draw: u32) -> VisBlendVsOut {
        VisBlendVsOut { clip: Vec4::splat(index as f32), world: Vec3::ZERO, id: draw }
    }
    pub fn vis_blend_varyings(input: VisBlendVsOut) -> VsOut {
        VsOut { clip: input.clip, world: input.world }
    }
    pub fn vis_in_front(frag: Vec4, coverage: u32) -> u32 {
        coverage & select(frag.z < 0.5, 1u32, 0u32)
    }
    pub fn vis_blend_kept(input: VsOut, front: bool, coverage: u32) -> bool {
        front && vis_in_front(input.clip, coverage) != 0u32
    }
    pub fn vis_blend_append(frag: Vec2, id: u32) {
        if msaa > 0 && blend {
            RECORDS[id] = frag.extend(0.0).extend(1.0);
        }
    }
    pub fn vis_blend_listed() -> u32 {
        3u32
    }
    pub fn vis_blend_write_args() {
        if msaa > 0 && blend {
            RECORDS[0] = Vec4::ONE;
        }
    }
    pub fn vis_blend_at(r: u32) -> BlendRecord {
        BlendRecord { next: r / 2u32, id: r, pixel: UVec2::splat(r) }
    }
    pub fn vis_blend_store(r: u32, color: Vec4) {
        if msaa > 0 && blend {
            RECORDS[r] = color;
        }
    }
    pub fn vis_blend_record(frag: Vec2, id: u32) -> u32 {
        id + (frag.x as u32)
    }
    pub fn vis_blend_color(r: u32) -> Vec4 {
        Vec4::splat(r as f32)
    }
}
"#;

fn with_frame(material: &str) -> String {
    format!("{FRAME}{VIS_FRAME}{BLEND_FRAME}{material}")
}

const TINTED: &str = r#"
#[material(frame = crate::mini_frame, visibility = crate::mini_vis, blended = crate::mini_blend, params = Tint)]
mod tinted {
    pub struct Tint { pub colour: Vec4 }
    fn surface(point: MaterialPoint, params: Tint) -> Surface {
        Surface { base_color: params.colour * point.world.x }
    }
}
"#;

#[test]
fn a_material_is_the_frame_around_its_surface_for_every_frame_variant() {
    let src = with_frame(TINTED);
    let file = syn::parse_file(&src).expect("parses");
    let modules = codegen::shader_modules(&file);
    assert_eq!(
        modules.len(),
        1,
        "the material comes out as one shader module"
    );
    let compiled = codegen::compile_source_all_with(&src, &[]).expect("parses");
    let (name, result) = &compiled[0];
    assert_eq!(name, "tinted");
    let c = result.as_ref().unwrap_or_else(|e| panic!("{e}"));
    let kept: Vec<&str> = (c.keys.iter().zip(&c.key_variant))
        .filter(|(_, v)| v.is_some())
        .map(|(k, _)| k.name.as_str())
        .collect();
    assert_eq!(
        kept.len(),
        34,
        "list × blend × scalarize less naive scalar, the kernels of 1, 2, 4 and 8 samples \
         with clustered lists, plain and scalarized, over the raster targets and over the \
         compute rasteriser's buffer (`vis64`), and the blended surfaces over that buffer \
         at each sample count, plain and scalarized: {kept:?}"
    );
    assert!(kept.contains(&"list2_scalar_msaa4_vis64"), "{kept:?}");
    assert!(kept.contains(&"list2_blend_scalar_msaa8_vis64"), "{kept:?}");
    assert!(
        !kept
            .iter()
            .any(|k| k.contains("_blend") && k.contains("_msaa") && !k.ends_with("_vis64")),
        "blended surfaces over the hardware raster's targets are the forward variants: {kept:?}"
    );
    assert!(
        !kept
            .iter()
            .any(|k| k.ends_with("_vis64") && !k.contains("_msaa")),
        "`vis64` is an axis of the kernels only: {kept:?}"
    );
    assert!(!kept.contains(&"list0_scalar"), "{kept:?}");
    assert!(
        kept.contains(&"list1_blend"),
        "the forward names are as they were: {kept:?}"
    );
    assert!(kept.contains(&"list2_scalar_msaa4"), "{kept:?}");
    for variant in &c.variants {
        let wgsl = &variant.wgsl;
        let over_samples = variant.names.iter().all(|n| n.contains("_msaa"));
        let blend = variant.names.iter().all(|n| n.contains("_blend"));
        let kernel = over_samples && !blend;
        let (present, absent): (&[&str], &[&str]) = match (over_samples, blend) {
            (true, false) => (
                &["fn vis_shade("],
                &[
                    "fn vs_forward(",
                    "fn fs_forward(",
                    "fn fs_gbuffer(",
                    "fn vs_blend(",
                    "fn vis_shade_blended(",
                ],
            ),
            (true, true) => (
                &[
                    "fn vs_forward(",
                    "fn vs_blend(",
                    "fn fs_blend_list(",
                    "fn vis_blend_args(",
                    "fn vis_shade_blended(",
                    "fn fs_blend_listed(",
                    "fn fs_forward_vis64(",
                    "vis_in_front(varyings.clip, coverage)",
                    "vis_point(vis_triangle(record.id), record.pixel)",
                    "vis_blend_append(input.clip.xy, input.id)",
                    "vis_blend_record(varyings.clip.xy, input.id)",
                ],
                &["fn vis_shade(", "fn fs_forward(", "fn fs_gbuffer("],
            ),
            (false, _) => (
                &["fn vs_forward(", "fn fs_forward(", "fn fs_gbuffer("],
                &[
                    "fn vis_shade(",
                    "fn fs_forward_vis64(",
                    "fn vs_blend(",
                    "fn fs_blend_list(",
                    "fn vis_shade_blended(",
                ],
            ),
        };
        for entry in present {
            assert!(wgsl.contains(entry), "{entry} missing:\n{wgsl}");
        }
        for entry in absent {
            assert!(!wgsl.contains(entry), "{entry} present:\n{wgsl}");
        }
        assert_eq!(
            wgsl.contains("var<storage, read_write> SUMS"),
            kernel,
            "{wgsl}"
        );
        assert_eq!(
            wgsl.contains("var<storage, read_write> RECORDS"),
            over_samples && blend,
            "{wgsl}"
        );
        assert!(
            wgsl.contains("@group(0) @binding(19) var<storage, read> PARAMS: array<Tint>;"),
            "{wgsl}"
        );
        assert!(
            wgsl.contains("surface(point, PARAMS[point.params])"),
            "{wgsl}"
        );
    }
}

fn refusal(material: &str) -> String {
    let file = syn::parse_file(material).expect("parses");
    let syn::Item::Mod(m) = &file.items[0] else {
        panic!("a module")
    };
    let attr = &m.attrs[0];
    let args = match &attr.meta {
        syn::Meta::List(l) => l.tokens.clone(),
        _ => proc_macro2::TokenStream::new(),
    };
    let mut item = m.clone();
    item.attrs.clear();
    match codegen::expand_material(args, quote::ToTokens::into_token_stream(item)) {
        Ok(_) => panic!("expanded: {material}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn materials_without_a_surface_or_with_the_frames_names_are_refused() {
    let e = refusal("#[material] mod m { fn shade(point: MaterialPoint) -> Surface { todo() } }");
    assert!(
        e.contains("declares `fn surface(point: MaterialPoint) -> Surface`"),
        "{e}"
    );
    let e = refusal(
        "#[material(params = P)] mod m { fn surface(point: MaterialPoint) -> Surface { x } }",
    );
    assert!(
        e.contains("`params = P` shades with `fn surface(point: MaterialPoint, params: P)"),
        "{e}"
    );
    let e = refusal(
        "#[material] mod m { fn surface(p: MaterialPoint) -> Surface { x } fn fs_forward() {} }",
    );
    assert!(
        e.contains("`fs_forward` is written by `#[material]`"),
        "{e}"
    );
    let e = refusal(
        "#[material(axes(tile: u32 = [8]))] mod m { fn surface(p: MaterialPoint) -> Surface { x } }",
    );
    assert!(e.contains("unknown `#[material]` argument `axes`"), "{e}");
}
