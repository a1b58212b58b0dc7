//! Blended surfaces over the compute rasteriser's frame, lit in compute.

/// The blended surfaces of the compute rasteriser's frame (a material's variants with `msaa`
/// above 0 and `blend`): their fragments are found by the hardware raster, lit by a compute
/// kernel, and blended by the hardware, in three steps.
///
/// 1. **Listing** (`fs_blend_list`). The blended draws are rastered through the vertex stage
///    `vis_blend_vertex`, which pulls the vertex from storage (`vis_geometry`'s
///    `pulled_vertex`) and so knows its triangle's ID. A fragment in front of the opaque
///    surface at one of its samples (`vis_in_front`), and not dropped as a single-sided back
///    face or by an alpha mask, appends a record `{next, ID, pixel}` to its pixel's list
///    (`vis_blend_append`). `BLEND_LISTS` starts with a header of `BLEND_LIST_HEADER` words
///    (`[0]` counts the records), then holds a word a pixel: its first record plus one (0:
///    none).
/// 2. **Lighting.** `vis_blend_write_args` (one invocation) writes into the header the
///    lighting's dispatch (a workgroup of 64 a 64 records) and which of the forward pass's two
///    blended pipelines draws (the counts of two count-draws). `vis_shade_blended`, one
///    invocation a record, rebuilds the fragment from its triangle (`vis_frame`'s `vis_point`,
///    at the pixel centre, as the fragment stage interpolates without sample shading), gives
///    it to the material's `surface` and lights it (`vis_radiance`: decals, the froxel's
///    lights, shadows); its colour and the surface's alpha go into the record.
/// 3. **Blending.** The forward pass draws the blended draws again, back to front, through
///    the same vertex stage (the clip position is `#[invariant]`, so the fragments are the
///    listing's). A fragment outputs its record's colour (`vis_blend_record`,
///    `vis_blend_color`) into the samples where it is in front of the opaque surface, and the
///    hardware blends them in draw order, as before.
///
/// The fragment stage runs far below the compute rate on some chips (the H200's graphics
/// units are a few of its SMs): lighting the courtyard's glass in its fragment stage took 0.71
/// of the forward pass's 0.79 ms at MSAA 4 (BENCHMARKS.md).
///
/// **Nothing is lost when the records run out.** A fragment past `BLEND_RECORDS`' capacity is
/// counted but not listed. The forward pass then draws with its other pipeline, whose fragment
/// stage (`fs_forward_vis64`) shades a fragment without a record itself
/// (`material_forward_from`), as before this library: the frame is the same, only slower. The
/// choice is the GPU's, in the frame (`vis_blend_write_args`), since only the GPU knows the
/// count: a fragment stage that may shade holds the registers of the whole lighting loop, and
/// ran the courtyard's listed glass at 0.30 ms, against 0.05 for the one that only outputs
/// records (`fs_blend_listed`; H200, MSAA 4, BENCHMARKS.md).
#[shader_dsl::library(
    axes(
        list: u32 = [0, 1, 2],
        blend: bool = [false, true],
        scalarize: bool = [false, true],
        msaa: u32 = [0, 1, 2, 4, 8],
        vis64: bool = [false, true],
    ),
    requires(subgroup = scalarize),
    uses(
        crate::visibility::vis_frame,
        crate::forward::material_frame,
        crate::forward::material_surface,
        crate::visibility::samples64::vis64_sample,
        crate::shared::view,
        crate::shared::material_uv,
        crate::shared::material_table,
        crate::shared::pbr,
        crate::shared::light_lists,
        crate::shared::surface_light,
        crate::shared::light_grid,
        crate::shared::shadow_atlas,
        crate::shared::decal_apply,
        crate::shared::octahedral,
        crate::visibility::geometry::vis_geometry,
        crate::shared::sample_pattern,
    ),
)]
pub mod vis_blend {
    /// Words before the pixels' heads in `BLEND_LISTS`: `[0]` the records appended (those past
    /// the capacity too); `[1..4]` the lighting's dispatch; `[4]` and `[5]` the draw counts of
    /// the forward pass's pipeline that outputs records and of the one that may shade
    /// (`vis_blend_write_args`).
    pub const BLEND_LIST_HEADER: u32 = 8;

    /// One listed blended fragment.
    pub struct BlendRecord {
        /// The pixel's next record plus one (0: the end of its list).
        pub next: u32,
        /// The fragment's triangle ID.
        pub id: u32,
        /// Its pixel.
        pub pixel: UVec2,
        /// Its lit colour (linear HDR radiance, then the surface's alpha) as two
        /// `pack2x16_float` words (the half floats of the `Rgba16Float` target it is blended
        /// into), written by `vis_shade_blended`.
        pub color: UVec2,
    }

    /// The header (`BLEND_LIST_HEADER`), then `[BLEND_LIST_HEADER + y × width + x]`: pixel
    /// `(x, y)`'s first record plus one (0: none). Zeroed before the listing.
    #[storage(group = 0, binding = 17, read_write)]
    #[when(msaa > 0 && blend)]
    static BLEND_LISTS: [Atomic<u32>];
    /// The records, in the order they were appended.
    #[storage(group = 0, binding = 18, read_write)]
    #[when(msaa > 0 && blend)]
    static BLEND_RECORDS: [BlendRecord];

    /// What the vertex stage of a blended draw passes on: the material frame's `VsOut`, and the
    /// triangle's ID.
    pub struct VisBlendVsOut {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub world: Vec3,
        #[location(1)]
        pub normal: Vec3,
        #[location(2)]
        pub uv: Vec2,
        #[location(3)]
        pub tangent: Vec4,
        #[location(4)]
        pub uv1: Vec2,
        #[location(5)]
        pub color: Vec4,
        #[location(6)]
        #[interpolate(flat)]
        pub material: u32,
        #[location(7)]
        #[interpolate(flat)]
        pub handedness: f32,
        /// The fragment's triangle ID (`vis_geometry`'s numbering).
        #[location(8)]
        #[interpolate(flat)]
        pub id: u32,
    }

    /// The colour of a blended fragment drawn over the compute rasteriser's frame, and the
    /// samples it goes to (`fs_forward_vis64`).
    pub struct VisBlendOut {
        #[location(0)]
        pub color: Vec4,
        #[builtin(sample_mask)]
        pub mask: u32,
    }

    /// The vertex stage of a blended draw drawn over the sequence index buffer: vertex `index`
    /// of draw `draw`, pulled from storage and placed by the material frame's
    /// `material_vertex`, with its triangle's ID.
    pub fn vis_blend_vertex(index: u32, draw: u32) -> VisBlendVsOut {
        let pulled = pulled_vertex(index, draw);
        let v = pulled.vertex;
        let o = material_vertex(
            vertex_position(v),
            vertex_normal(v),
            UV0[v],
            TANGENTS[v],
            UV1[v],
            COLORS[v],
            draw,
        );
        VisBlendVsOut {
            clip: o.clip,
            world: o.world,
            normal: o.normal,
            uv: o.uv,
            tangent: o.tangent,
            uv1: o.uv1,
            color: o.color,
            material: o.material,
            handedness: o.handedness,
            id: pulled.triangle,
        }
    }

    /// `input` as the material frame's fragment functions take it.
    pub fn vis_blend_varyings(input: VisBlendVsOut) -> VsOut {
        VsOut {
            clip: input.clip,
            world: input.world,
            normal: input.normal,
            uv: input.uv,
            tangent: input.tangent,
            uv1: input.uv1,
            color: input.color,
            material: input.material,
            handedness: input.handedness,
        }
    }

    /// With `vis64`: the samples of `coverage` (the fragment's `sample_mask` input) where a
    /// blended fragment at `frag` (its `position` built-in: the pixel centre and the depth
    /// there) is no farther than the opaque surface in `VIS64` (`LessEqual`, the hardware
    /// raster's blended depth test). Its depth at a sample is taken on its plane through the
    /// screen derivatives of `frag.z`, as the hardware interpolates depth at the sample; 0
    /// where the module has no `VIS64`.
    pub fn vis_in_front(frag: Vec4, coverage: u32) -> u32 {
        let slope = Vec2::new(dpdx(frag.z), dpdy(frag.z));
        let mut mask = 0u32;
        if vis64 && msaa > 0 {
            let p = frag.xy().floor().as_uvec2();
            let first = (p.y * VIS.screen.x + p.x) * msaa;
            for s in 0u32..msaa {
                let depth = frag.z + slope.dot(sample_offset(s) - Vec2::splat(0.5));
                let opaque = vis64_depth(VIS64[first + s]);
                if ((coverage >> s) & 1u32) != 0u32 && depth <= opaque {
                    mask = mask | (1u32 << s);
                }
            }
        }
        mask
    }

    /// Where pixel `p`'s list starts in `BLEND_LISTS`.
    fn vis_blend_head(p: UVec2) -> u32 {
        let mut head = 0u32;
        if msaa > 0 {
            head = BLEND_LIST_HEADER + p.y * VIS.screen.x + p.x;
        }
        head
    }

    /// Whether the listing keeps `input` (in front of the opaque surface at a sample of
    /// `coverage`, facing `front`): not a single-sided material's back face (the material
    /// frame's `forward_facing`, which discards it), nor cut by the material's alpha mask.
    /// Takes its derivatives first.
    pub fn vis_blend_kept(input: VsOut, front: bool, coverage: u32) -> bool {
        let d = fragment_derivatives(input);
        let mut kept = vis_in_front(input.clip, coverage) != 0u32;
        if kept {
            // Discards a single-sided material's back face.
            let _facing = forward_facing(input, front);
            kept = !masked_out(input.material, d.uv, input.color.w);
        }
        kept
    }

    /// Appends triangle `id`'s fragment at window position `frag` to its pixel's list; past
    /// the records' capacity it is only counted (the forward pass shades it itself).
    pub fn vis_blend_append(frag: Vec2, id: u32) {
        if msaa > 0 && blend {
            let slot = BLEND_LISTS[0].fetch_add(1u32);
            if slot < BLEND_RECORDS.len() {
                let head = vis_blend_head(frag.floor().as_uvec2());
                let next = BLEND_LISTS[head].swap(slot + 1u32);
                BLEND_RECORDS[slot] = BlendRecord {
                    next,
                    id,
                    pixel: frag.floor().as_uvec2(),
                    color: UVec2::ZERO,
                };
            }
        }
    }

    /// The records listed this frame (those within the capacity).
    pub fn vis_blend_listed() -> u32 {
        let mut listed = 0u32;
        if msaa > 0 && blend {
            listed = BLEND_LISTS[0].load().min(BLEND_RECORDS.len());
        }
        listed
    }

    /// Writes the header after the listing: the lighting's dispatch (64 records a workgroup)
    /// and the draw counts of the forward pass's two blended pipelines, every blended draw
    /// (`VIS.blended_draws`) to the one that outputs records and none to the one that may
    /// shade, or, where fragments came past the capacity, the other way round.
    pub fn vis_blend_write_args() {
        if msaa > 0 && blend {
            let overflow = BLEND_LISTS[0].load() > BLEND_RECORDS.len();
            let draws = VIS.blended_draws;
            BLEND_LISTS[1].store((vis_blend_listed() + 63u32) / 64u32);
            BLEND_LISTS[2].store(1u32);
            BLEND_LISTS[3].store(1u32);
            BLEND_LISTS[4].store(select(overflow, 0u32, draws));
            BLEND_LISTS[5].store(select(overflow, draws, 0u32));
        }
    }

    /// Pixel `p`'s first record plus one (0: none).
    pub fn vis_blend_first(p: UVec2) -> u32 {
        let mut first = 0u32;
        if msaa > 0 && blend {
            first = BLEND_LISTS[vis_blend_head(p)].load();
        }
        first
    }

    /// Record `r` (plus one) as it is.
    pub fn vis_blend_at(r: u32) -> BlendRecord {
        let mut record = BlendRecord {
            next: 0u32,
            id: 0u32,
            pixel: UVec2::ZERO,
            color: UVec2::ZERO,
        };
        if msaa > 0 && blend {
            record = BLEND_RECORDS[r - 1u32];
        }
        record
    }

    /// The record (plus one) of triangle `id`'s fragment at window position `frag`; 0 where
    /// its pixel's list has none (the fragment came past the capacity).
    pub fn vis_blend_record(frag: Vec2, id: u32) -> u32 {
        let mut r = vis_blend_first(frag.floor().as_uvec2());
        let mut found = 0u32;
        while r != 0u32 {
            let record = vis_blend_at(r);
            if record.id == id {
                found = r;
                r = 0u32;
            } else {
                r = record.next;
            }
        }
        found
    }

    /// Stores `color` (linear HDR radiance and alpha) in record `r` (plus one), clamped to
    /// the half floats' range.
    pub fn vis_blend_store(r: u32, color: Vec4) {
        if msaa > 0 && blend {
            let c = color.clamp(Vec4::splat(-65504.0), Vec4::splat(65504.0));
            let packed = UVec2::new(pack2x16_float(c.xy()), pack2x16_float(c.zw()));
            let record = BLEND_RECORDS[r - 1u32];
            BLEND_RECORDS[r - 1u32] = BlendRecord {
                next: record.next,
                id: record.id,
                pixel: record.pixel,
                color: packed,
            };
        }
    }

    /// The colour `vis_shade_blended` stored in record `r` (plus one).
    pub fn vis_blend_color(r: u32) -> Vec4 {
        let packed = vis_blend_at(r).color;
        let rg = unpack2x16_float(packed.x);
        let ba = unpack2x16_float(packed.y);
        Vec4::new(rg.x, rg.y, ba.x, ba.y)
    }
}
