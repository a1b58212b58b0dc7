// Golden: a graph of libraries as a shader library crate publishes it, in one text. `units`
// is a leaf; `lighting` uses it and owns a binding contract (group 0, bindings 0-1, one of them
// only where its axis asks) and an entry-point IO struct for its users; `varyings` uses `units`
// too, so the module reaches `units` along two routes (a diamond, merged once). The module names
// one library by another crate's path (`engine_lib::lighting`): source-text compilation
// resolves a path by its last segment, as tools do for libraries of other crates.

#[library]
pub mod units {
    pub const HALF: f32 = 0.5;
    pub fn halve(x: f32) -> f32 {
        x * HALF
    }
}

#[library(axes(listed: bool = [false, true]), uses(crate::units))]
pub mod lighting {
    pub struct Lamp {
        pub position: Vec3,
        pub power: f32,
    }

    #[storage(group = 0, binding = 0)]
    static LAMPS: [Lamp];
    #[storage(group = 0, binding = 1)]
    #[when(listed)]
    static LIST: [u32];

    /// Lamp `i` of the frame: through the list where there is one.
    pub fn lamp(i: u32) -> Lamp {
        let mut index = i;
        if listed {
            index = LIST[i];
        }
        LAMPS[index]
    }

    pub fn received(p: Vec3, i: u32) -> f32 {
        let l = lamp(i);
        let d = l.position - p;
        halve(l.power) / d.dot(d).max(1.0e-4)
    }
}

#[library(uses(crate::units))]
pub mod varyings {
    pub struct Varying {
        #[builtin(position)]
        #[invariant]
        pub clip: Vec4,
        #[location(0)]
        pub world: Vec3,
    }

    pub fn dimmed(v: Varying) -> f32 {
        halve(v.world.y)
    }
}

#[shader(
    axes(listed: bool = [false, true] => "listed"),
    uses(engine_lib::lighting, crate::varyings),
)]
pub mod lit_points {
    #[uniform(group = 1, binding = 0)]
    static COUNT: UVec4;

    #[vertex]
    pub fn vs(#[location(0)] p: Vec3) -> Varying {
        Varying {
            clip: p.extend(1.0),
            world: p,
        }
    }

    #[fragment]
    pub fn fs(input: Varying) -> Vec4 {
        let mut sum = dimmed(input);
        for i in 0u32..COUNT.x {
            sum += received(input.world, i);
        }
        Vec4::new(sum, sum, sum, HALF)
    }
}
