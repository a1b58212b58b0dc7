// Golden: operators, casts, swizzles, constructors, math/geometric methods, select, bit
// counting, packing, matrices and std constants.
#[shader_dsl::shader]
pub mod expressions {
    pub struct Io {
        pub m: Mat4,
        pub n: Mat3,
        pub v: Vec4,
        pub u: UVec4,
        pub i: IVec2,
        pub f: f32,
        pub bits: u32,
    }

    const HALF: f32 = 0.5;
    const MASK: u32 = (1u32 << 4) - 1;
    const UP: Vec3 = Vec3::new(0.0, 1.0, 0.0);

    #[storage(group = 0, binding = 0, read_write)]
    static IO: Io;

    fn math(x: f32, v: Vec3) -> f32 {
        let a = x.abs().sqrt().floor().ceil().round().fract().trunc();
        let b = x.sin() + x.cos() * x.tan() - x.asin().acos().atan() + x.atan2(HALF);
        let c = x.exp().ln() + x.exp2().log2() + x.powf(2.0) + x.signum() + x.to_radians().to_degrees();
        let d = x.clamp(0.0, 1.0).min(HALF).max(0.25).saturate() + x.inverse_sqrt() + x.mul_add(2.0, 1.0);
        let e = x.lerp(1.0, 0.5) + x.smoothstep(0.0, 1.0) + x.step(0.5) + x.sinh() + x.cosh() + x.tanh();
        let g = v.dot(Vec3::ONE) + v.length() + v.length_squared() + v.distance(Vec3::ZERO);
        let w = v.normalize().cross(UP).reflect(Vec3::X) + v.lerp(Vec3::splat(1.0), 0.25);
        a + b + c + d + e + g + w.x + core::f32::consts::PI + f32::EPSILON
    }

    #[compute(workgroup_size(1))]
    pub fn main(#[builtin(local_invocation_id)] lid: UVec3) {
        let v = IO.v;
        let xy = v.xy();
        let zyx = v.zyx();
        let v3 = xy.extend(1.0);
        let v4 = Vec4::new(xy.x, xy.y, zyx.z, 1.0) + Vec4::new(v3.x, v3.y, v3.z, 0.0) * 2.0;
        let t = v4.truncate() - v3 / 4.0;
        let m = IO.m * Mat4::IDENTITY;
        let p = m * v4;
        let col = m.col(1) + m.x_axis;
        let n = IO.n.transpose() * t;
        let det = IO.m.determinant() + Mat3::from_cols(t, n, Vec3::Z).determinant();
        let u = IO.u;
        let bits = u.x.count_ones() + u.y.leading_zeros() + u.z.trailing_zeros() + u.w.reverse_bits();
        let shifted = (bits << 2u32) >> 1 | (bits & MASK) ^ !bits;
        let i = IO.i;
        let signed = -i.x % 3 + (i.y >> 1) + (lid.x as i32);
        let conv = u.xy().as_vec2() + i.as_vec2() + xy.as_uvec2().as_vec2() + xy.as_ivec2().as_vec2();
        let cmp = (v.x < v.y) && !(v.z >= 0.0) || v.w != 1.0;
        let s = select(cmp, p.x, col.y);
        let sv = select(v.x > 0.0, Vec2::X, Vec2::Y);
        let packed = pack4x8_unorm(v) ^ pack4x8_snorm(v) ^ pack2x16_unorm(xy) ^ pack2x16_snorm(xy);
        let unpacked = unpack4x8_unorm(packed) + unpack4x8_snorm(packed) + unpack2x16_unorm(packed).xyxy() + unpack2x16_snorm(packed).xyxy();
        let big = u32::MAX - (i32::MAX as u32) + (f32::MAX as u32) + (true as u32);
        IO.f = math(s + det + conv.x + sv.y + unpacked.w + (signed as f32), t) + (u32::MIN as f32);
        IO.bits = shifted + big + packed + (MASK as u32);
        IO.v = Vec4::new(p.x, p.y, p.z, p.w).abs().min(Vec4::splat(HALF)).max(-Vec4::ONE);
        IO.u.x = u.x.min(3u32).max(1u32).clamp(1u32, 2u32);
    }
}
