//! `#[material]`: a material written as one DSL function, expanded into a `#[shader]` module
//! whose entry points are the renderer's material frame around it.
//!
//! The module declares `fn surface(point: MaterialPoint) -> Surface`, or with
//! `params = P` (a struct of the module or of a library it uses) `fn surface(point:
//! MaterialPoint, params: P) -> Surface`; the expansion adds
//! * the frame library (`frame = path`, by default `shaders_gen::forward::material_frame`)
//!   to `uses(..)`, and the frame's axes (`list`, `blend`, `scalarize`, with its exclusion and
//!   subgroup requirement);
//! * with `params`, the binding `PARAMS: [P]` at group 0, binding 19 (the renderer binds every
//!   parameter record of the material's instances there, and the material record's `params`
//!   picks one);
//! * the entry points `vs_forward`, `fs_forward` and `fs_gbuffer`, which call the frame's
//!   `material_vertex`, `forward_facing`, `material_point`, `material_forward` and
//!   `material_gbuffer` around `surface`;
//! * the visibility path's kernel `vis_shade`, which calls the visibility frame's
//!   (`visibility = path`, by default `shaders_gen::visibility::vis_frame`) `vis_point`,
//!   `vis_radiance` and the pixel's sample loop around `surface`. It exists in the variants of
//!   the axis `msaa` above 0 (the raster pass's sample count; clustered lists, opaque), and the
//!   forward entry points in those at 0, whose names the axis leaves as they were (`unless 0`);
//! * for blended surfaces drawn over the compute rasteriser's frame (`msaa` above 0 with
//!   `blend` and `vis64`), the three steps of the blended frame (`blended = path`, by default
//!   `shaders_gen::visibility::vis_blend`): `vs_blend`, the vertex stage that pulls the vertex
//!   and knows its triangle; `fs_blend_list`, which lists the fragments in front of the opaque
//!   surface (`vis_blend_kept`, `vis_blend_append`); `vis_blend_args`, which writes the
//!   lighting's dispatch and picks the blended pipeline (`vis_blend_write_args`);
//!   `vis_shade_blended`, one invocation a record, which lights each listed fragment through
//!   `vis_point` and `vis_radiance` around `surface` and stores its colour; `fs_blend_listed`,
//!   which outputs that colour into the samples where `vis_in_front` finds the fragment in
//!   front of the opaque surface (through the `sample_mask` output, so no depth target is
//!   needed); and `fs_forward_vis64`, which does the same but shades a fragment the records
//!   had no room for itself (`material_point_from`, `material_forward_from`, its derivatives
//!   taken before it may be discarded). `vs_forward` stays, for the overlay's eraser.
//!
//! What the frame's functions do, and the names the renderer expects, are the frame library's
//! contract; this expansion only writes the calls.

use proc_macro2::{Span, TokenStream};
use quote::{ToTokens, quote, quote_spanned};
use syn::parse::{Parse, ParseStream};
use syn::spanned::Spanned;
use syn::{Ident, Token};

/// The items the expansion adds; a module may not declare them itself.
const RESERVED: [&str; 11] = [
    "vs_forward",
    "fs_forward",
    "fs_forward_vis64",
    "fs_gbuffer",
    "vis_shade",
    "vs_blend",
    "fs_blend_list",
    "vis_shade_blended",
    "vis_blend_args",
    "fs_blend_listed",
    "PARAMS",
];

/// The parsed arguments of `#[material(..)]`.
struct MaterialArgs {
    frame: syn::Path,
    visibility: syn::Path,
    blended: syn::Path,
    params: Option<syn::Type>,
    uses: Vec<syn::Path>,
}

impl Parse for MaterialArgs {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let mut args = MaterialArgs {
            frame: syn::parse_quote!(shaders_gen::forward::material_frame),
            visibility: syn::parse_quote!(shaders_gen::visibility::vis_frame),
            blended: syn::parse_quote!(shaders_gen::visibility::vis_blend),
            params: None,
            uses: Vec::new(),
        };
        while !input.is_empty() {
            let key: Ident = input.parse()?;
            match key.to_string().as_str() {
                "frame" => {
                    input.parse::<Token![=]>()?;
                    args.frame = input.parse()?;
                }
                "visibility" => {
                    input.parse::<Token![=]>()?;
                    args.visibility = input.parse()?;
                }
                "blended" => {
                    input.parse::<Token![=]>()?;
                    args.blended = input.parse()?;
                }
                "params" => {
                    input.parse::<Token![=]>()?;
                    args.params = Some(input.parse()?);
                }
                "uses" => {
                    let content;
                    syn::parenthesized!(content in input);
                    let paths = content.parse_terminated(syn::Path::parse, Token![,])?;
                    args.uses.extend(paths);
                }
                other => {
                    return Err(syn::Error::new(
                        key.span(),
                        format!(
                            "unknown `#[material]` argument `{other}`: a material takes `frame = path` (the material frame library, by default `shaders_gen::forward::material_frame`), `visibility = path` (the visibility path's frame, by default `shaders_gen::visibility::vis_frame`), `blended = path` (the blended surfaces' frame over the compute rasteriser's, by default `shaders_gen::visibility::vis_blend`), `params = Type` (its parameter struct) and `uses(..)` (libraries); its axes are the frame's"
                        ),
                    ));
                }
            }
            if !input.is_empty() {
                input.parse::<Token![,]>()?;
            }
        }
        Ok(args)
    }
}

/// `#[material(..)]`: the module with the frame's entry points, compiled as `#[shader]`.
pub fn expand_material(args: TokenStream, item: TokenStream) -> syn::Result<TokenStream> {
    let (shader_args, module) = as_shader(args, syn::parse2(item)?)?;
    crate::expand(shader_args, module.into_token_stream())
}

/// A `#[material(args)]` module as the `#[shader(..)]` module it expands to: the shader's
/// arguments and the module with the entry points (and `PARAMS`) added. Tools that compile
/// source text without the proc-macro (`sources::shader_modules`) take materials through it.
pub fn as_shader(
    args: TokenStream,
    mut module: syn::ItemMod,
) -> syn::Result<(TokenStream, syn::ItemMod)> {
    let args: MaterialArgs = syn::parse2(args)?;
    let Some((_, content)) = module.content.as_mut() else {
        return Err(syn::Error::new(
            module.ident.span(),
            "a material module must be inline: `mod name { .. }`",
        ));
    };
    check_reserved(content)?;
    let surface = surface_fn(&module.ident, content)?;
    let wanted = if args.params.is_some() { 2 } else { 1 };
    if surface.sig.inputs.len() != wanted {
        let message = match &args.params {
            Some(p) => format!(
                "a material with `params = {}` shades with `fn surface(point: MaterialPoint, params: {}) -> Surface`",
                p.to_token_stream(),
                p.to_token_stream()
            ),
            None => "a material shades with `fn surface(point: MaterialPoint) -> Surface` (add `params = Type` to `#[material]` to give it a parameter struct)".to_string(),
        };
        return Err(syn::Error::new(surface.sig.inputs.span(), message));
    }
    let span = surface.sig.ident.span();
    for item in entry_points(span, args.params.as_ref()) {
        content.push(item);
    }
    let frame = &args.frame;
    let visibility = &args.visibility;
    let blended = &args.blended;
    let uses = &args.uses;
    let shader_args = quote! {
        axes(
            list: u32 = [0, 1, 2] => "list",
            blend: bool = [false, true] => "blend",
            scalarize: bool = [false, true] => "scalar",
            msaa: u32 = [0, 1, 2, 4, 8] => "msaa" unless 0,
            vis64: bool = [false, true] => "vis64",
        ),
        exclude(list == 0 && scalarize),
        exclude(msaa > 0 && list != 2),
        exclude(msaa > 0 && blend && !vis64),
        exclude(msaa == 0 && vis64),
        requires(subgroup = scalarize),
        uses(#frame, #visibility, #blended #(, #uses)*),
    };
    Ok((shader_args, module))
}

/// A material may not declare what the expansion adds.
fn check_reserved(content: &[syn::Item]) -> syn::Result<()> {
    for item in content {
        let ident = match item {
            syn::Item::Fn(f) => Some(f.sig.ident.clone()),
            syn::Item::Verbatim(tokens) => static_name(tokens),
            _ => None,
        };
        if let Some(ident) = ident.filter(|i| RESERVED.contains(&i.to_string().as_str())) {
            return Err(syn::Error::new(
                ident.span(),
                format!(
                    "`{ident}` is written by `#[material]` (its entry points `vs_forward`, `fs_forward`, `fs_gbuffer`, `vis_shade`, `vs_blend`, `fs_blend_list`, `vis_blend_args`, `vis_shade_blended`, `fs_blend_listed` and `fs_forward_vis64`, and `PARAMS`, the parameter records); a material declares its `surface` function, and may call other functions of its own"
                ),
            ));
        }
    }
    Ok(())
}

/// The name of a `static` item (which syn keeps as verbatim tokens): the identifier after
/// `static` (and `mut`).
fn static_name(tokens: &TokenStream) -> Option<Ident> {
    let mut after_static = false;
    for tree in tokens.clone() {
        if let proc_macro2::TokenTree::Ident(ident) = tree {
            if after_static && ident != "mut" {
                return Some(ident);
            }
            after_static |= ident == "static";
        }
    }
    None
}

/// The module's `fn surface`.
fn surface_fn(name: &Ident, content: &[syn::Item]) -> syn::Result<syn::ItemFn> {
    content
        .iter()
        .find_map(|item| match item {
            syn::Item::Fn(f) if f.sig.ident == "surface" => Some(f.clone()),
            _ => None,
        })
        .ok_or_else(|| {
            syn::Error::new(
                name.span(),
                "a material module declares `fn surface(point: MaterialPoint) -> Surface`: the material frame shades what it returns",
            )
        })
}

/// The entry points around `surface` (its calls spanned at `surface`'s name, so a mismatch is
/// reported at the material's own function), and the parameter binding.
fn entry_points(span: Span, params: Option<&syn::Type>) -> Vec<syn::Item> {
    let call = match params {
        Some(_) => quote_spanned!(span=> surface(point, PARAMS[point.params])),
        None => quote_spanned!(span=> surface(point)),
    };
    let mut items: Vec<syn::Item> = vec![
        syn::parse_quote! {
            #[vertex]
            #[when(msaa == 0 || blend)]
            pub fn vs_forward(
                #[location(0)] position: Vec3,
                #[location(1)] normal: Vec3,
                #[location(2)] uv: Vec2,
                #[location(3)] tangent: Vec4,
                #[location(4)] uv1: Vec2,
                #[location(5)] color: Vec4,
                #[builtin(instance_index)] draw_index: u32,
            ) -> VsOut {
                material_vertex(position, normal, uv, tangent, uv1, color, draw_index)
            }
        },
        syn::parse_quote! {
            #[fragment]
            #[when(msaa == 0)]
            pub fn fs_forward(input: VsOut, #[builtin(front_facing)] front: bool) -> Vec4 {
                let point = material_point(input, forward_facing(input, front));
                material_forward(input, point, #call)
            }
        },
        syn::parse_quote! {
            /// A blended draw's vertex over the compute rasteriser's frame, pulled from
            /// storage, with its triangle's ID.
            #[vertex]
            #[when(msaa > 0 && blend)]
            pub fn vs_blend(
                #[builtin(vertex_index)] index: u32,
                #[builtin(instance_index)] draw: u32,
            ) -> VisBlendVsOut {
                vis_blend_vertex(index, draw)
            }
        },
        syn::parse_quote! {
            /// Lists a blended fragment in front of the opaque surface for
            /// `vis_shade_blended`.
            #[fragment]
            #[when(msaa > 0 && blend)]
            pub fn fs_blend_list(
                input: VisBlendVsOut,
                #[builtin(front_facing)] front: bool,
                #[builtin(sample_mask)] coverage: u32,
            ) {
                if vis_blend_kept(vis_blend_varyings(input), front, coverage) {
                    vis_blend_append(input.clip.xy(), input.id);
                }
            }
        },
        syn::parse_quote! {
            /// After the listing: the lighting's dispatch and the blended pipeline's choice.
            #[compute(workgroup_size(1, 1, 1))]
            #[when(msaa > 0 && blend)]
            pub fn vis_blend_args() {
                vis_blend_write_args();
            }
        },
        syn::parse_quote! {
            /// One listed blended fragment (64 a workgroup): lit, its colour and alpha stored
            /// in its record.
            #[compute(workgroup_size(64, 1, 1))]
            #[when(msaa > 0 && blend)]
            pub fn vis_shade_blended(#[builtin(global_invocation_id)] gid: UVec3) {
                let r = gid.x + 1u32;
                if r <= vis_blend_listed() {
                    let record = vis_blend_at(r);
                    let v = vis_point(vis_triangle(record.id), record.pixel);
                    let point = v.point;
                    let s = #call;
                    vis_blend_store(r, vis_radiance(v, s).extend(s.base_color.w));
                }
            }
        },
        syn::parse_quote! {
            /// A listed blended fragment over the compute rasteriser's frame: its record's
            /// colour drawn into the samples where it is in front of the opaque surface in
            /// `VIS64`, as a depth test would (the pipeline of a frame whose fragments all
            /// found room).
            #[fragment]
            #[when(msaa > 0 && blend)]
            pub fn fs_blend_listed(
                input: VisBlendVsOut,
                #[builtin(sample_mask)] coverage: u32,
            ) -> VisBlendOut {
                let mask = vis_in_front(input.clip, coverage);
                let r = vis_blend_record(input.clip.xy(), input.id);
                if mask == 0u32 || r == 0u32 {
                    discard();
                }
                VisBlendOut { color: vis_blend_color(r), mask }
            }
        },
        syn::parse_quote! {
            /// A blended fragment over the compute rasteriser's frame: its listed colour (or,
            /// past the records' capacity, its own shading) drawn into the samples where it is
            /// in front of the opaque surface in `VIS64`, as a depth test would.
            #[fragment]
            #[when(msaa > 0 && blend)]
            pub fn fs_forward_vis64(
                input: VisBlendVsOut,
                #[builtin(front_facing)] front: bool,
                #[builtin(sample_mask)] coverage: u32,
            ) -> VisBlendOut {
                let varyings = vis_blend_varyings(input);
                // Every derivative before the discard (see `fragment_derivatives`).
                let d = fragment_derivatives(varyings);
                let mask = vis_in_front(varyings.clip, coverage);
                if mask == 0u32 {
                    discard();
                }
                let r = vis_blend_record(varyings.clip.xy(), input.id);
                let mut color = Vec4::ZERO;
                if r != 0u32 {
                    color = vis_blend_color(r);
                } else {
                    let point = material_point_from(varyings, forward_facing(varyings, front), d);
                    color = material_forward_from(varyings, point, #call, d);
                }
                VisBlendOut { color, mask }
            }
        },
        syn::parse_quote! {
            #[fragment]
            #[when(msaa == 0)]
            pub fn fs_gbuffer(input: VsOut, #[builtin(front_facing)] front: bool) -> GBufferOut {
                let point = material_point(input, front);
                material_gbuffer(input, point, #call)
            }
        },
        syn::parse_quote! {
            /// One pixel (8 × 8 a workgroup): each distinct triangle of its samples whose
            /// material is this program's, shaded once and weighted by its samples. Round `k`
            /// shades each pixel's `k`-th distinct ID, so a subgroup shades as many times as
            /// its pixel with the most IDs, whichever samples hold them.
            #[compute(workgroup_size(8, 8, 1))]
            #[when(msaa > 0 && !blend)]
            pub fn vis_shade(#[builtin(global_invocation_id)] gid: UVec3) {
                let p = gid.xy();
                if vis_on_screen(p) {
                    let mut total = vis_begin(p);
                    let mut kinds = 0u32;
                    let mut left = vis_all_samples();
                    for _round in 0u32..msaa {
                        if left != 0u32 {
                            let id = vis_id_at(p, left.trailing_zeros());
                            let seen = vis_samples_of(p, id, left);
                            left = left ^ seen;
                            kinds += 1u32;
                            if id != 0u32 {
                                let tri = vis_triangle(id);
                                if vis_shades(tri) {
                                    let v = vis_point(tri, p);
                                    let point = v.point;
                                    total += vis_radiance(v, #call) * (seen.count_ones() as f32);
                                }
                            }
                        }
                    }
                    vis_finish(p, total, kinds);
                }
            }
        },
    ];
    if let Some(ty) = params {
        items.push(syn::Item::Verbatim(quote! {
            /// The parameter records of every material of this program (the material record's
            /// `params` picks one).
            #[storage(group = 0, binding = 19)]
            static PARAMS: [#ty];
        }));
    }
    items
}
