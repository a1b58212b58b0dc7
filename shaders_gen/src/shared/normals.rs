//! Octahedral unit-vector encoding: the G-buffer's normals in two numbers each.

/// `octahedral_encode` folds a unit vector onto the octahedron `|x| + |y| + |z| = 1` and its
/// lower half onto the outer triangles of the square, giving `[−1, 1]²`; `octahedral_decode`
/// inverts it. Two 16-bit floats per normal keep the round trip within about 0.001 rad (Cigolle
/// et al., "A Survey of Efficient Representations for Independent Unit Vectors", JCGT 2014).
#[shader_dsl::library]
pub mod octahedral {
    /// `±1` by the sign of each component, with `+1` for zero (WGSL's `sign` gives 0 there).
    fn sign_not_zero(v: Vec2) -> Vec2 {
        Vec2::new(select(v.x >= 0.0, 1.0, -1.0), select(v.y >= 0.0, 1.0, -1.0))
    }

    /// The octahedral coordinates of unit vector `n`, in `[−1, 1]²`.
    pub fn octahedral_encode(n: Vec3) -> Vec2 {
        let p = n.xy() / (n.x.abs() + n.y.abs() + n.z.abs());
        let mut e = p;
        if n.z < 0.0 {
            e = (Vec2::ONE - Vec2::new(p.y.abs(), p.x.abs())) * sign_not_zero(p);
        }
        e
    }

    /// The unit vector of octahedral coordinates `e`.
    pub fn octahedral_decode(e: Vec2) -> Vec3 {
        let z = 1.0 - e.x.abs() - e.y.abs();
        let mut xy = e;
        if z < 0.0 {
            xy = (Vec2::ONE - Vec2::new(e.y.abs(), e.x.abs())) * sign_not_zero(e);
        }
        xy.extend(z).normalize()
    }
}
