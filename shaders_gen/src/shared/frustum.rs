//! A box against a view frustum, as the scene-culling kernels test each draw.

/// `draw_in_frustum`: whether an axis-aligned world box meets a frustum of six planes (inside:
/// `dot(plane.xyz, p) + plane.w >= 0`, planes normalised by the host). A box is outside when it
/// lies wholly on the outer side of one plane, tested at the corner furthest along the plane's
/// normal, with a slack of `slack` world units so rounding never removes a box that touches
/// the frustum. An empty box (min above max) is kept.
#[shader_dsl::library]
pub mod box_frustum {
    /// A view frustum's six planes.
    pub struct Frustum {
        pub left: Vec4,
        pub right: Vec4,
        pub bottom: Vec4,
        pub top: Vec4,
        pub near: Vec4,
        pub far: Vec4,
    }

    /// A draw's bounds in world space (`w` unused).
    pub struct DrawBox {
        pub min: Vec4,
        pub max: Vec4,
    }

    /// Whether `b` reaches the inner side of `plane`, `slack` included.
    fn reaches(plane: Vec4, b: DrawBox, slack: f32) -> bool {
        let far_corner = Vec3::new(
            select(plane.x >= 0.0, b.max.x, b.min.x),
            select(plane.y >= 0.0, b.max.y, b.min.y),
            select(plane.z >= 0.0, b.max.z, b.min.z),
        );
        plane.xyz().dot(far_corner) + plane.w >= -slack
    }

    /// Whether `b` meets `f`.
    pub fn draw_in_frustum(f: Frustum, b: DrawBox, slack: f32) -> bool {
        if b.min.x > b.max.x {
            return true;
        }
        reaches(f.left, b, slack)
            && reaches(f.right, b, slack)
            && reaches(f.bottom, b, slack)
            && reaches(f.top, b, slack)
            && reaches(f.near, b, slack)
            && reaches(f.far, b, slack)
    }
}
