//! The reflected layout of a test variant as wgpu layout entries (`shader_bind::bind_group_layout_entries`).

use super::test_variant::VARIANT;
use shader_bind::bind_group_layout_entries;

#[test]
fn groups_map_to_wgpu_entries() {
    let g0 = bind_group_layout_entries(&VARIANT, 0);
    assert_eq!(g0.len(), 2);
    assert_eq!(g0[0].binding, 0);
    assert_eq!(g0[0].visibility, wgpu::ShaderStages::COMPUTE);
    assert!(matches!(
        g0[0].ty,
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            min_binding_size: Some(s),
            ..
        } if s.get() == 80
    ));
    assert_eq!(
        g0[1].visibility,
        wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT
    );
    assert!(matches!(
        g0[1].ty,
        wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Depth,
            multisampled: true,
            ..
        }
    ));
    let g1 = bind_group_layout_entries(&VARIANT, 1);
    assert!(matches!(
        g1[0].ty,
        wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: false },
            ..
        }
    ));
    assert_eq!(VARIANT.group_count(), 2);
}
