// Golden: comparisons and shifts in every comma-separated list position. WGSL's template-list
// discovery would read `f(a < b, c > d)` as a template `a<b, c>`; the printer parenthesises
// these list items so each of the lines below parses.
#[shader_dsl::shader]
pub mod template_lists {
    pub struct Io {
        pub a: u32,
        pub b: u32,
        pub c: i32,
        pub d: i32,
        pub x: f32,
        pub y: f32,
        pub out: UVec4,
    }

    #[storage(group = 0, binding = 0, read_write)]
    static IO: Io;

    fn both(p: bool, q: bool) -> u32 {
        select(p && q, 1u32, 0u32)
    }

    fn shifted(p: bool, s: u32) -> u32 {
        select(p, s, 0u32)
    }

    #[compute(workgroup_size(1))]
    pub fn main() {
        let a = IO.a;
        let b = IO.b;
        let c = IO.c;
        let d = IO.d;
        // Builtin arguments (the example).
        let up = IO.x < IO.y;
        let builtin = select(up, a > b, a < b);
        // Module-function arguments, with `<` then `>`, and `<` then `>>`.
        let call = both(c < d, c > d) + shifted(a < b, a >> 1u32);
        // Constructor arguments and an array literal.
        let v = BVec2::new(a <= b, a >= b);
        let arr = [c < d, c > d, a < b];
        // An index computed from a comparison next to a shift.
        let table = [10u32, 20u32];
        let index = table[(a < b) as u32] + table[((b >> 3u32) < 2u32) as u32];
        // A cast inside a list with a later `>`.
        let cast = UVec2::new((c < d) as u32, (a > b) as u32);
        IO.out = UVec4::new(
            select(builtin, 1u32, 0u32) + call,
            select(v.x && arr[0] || arr[1], 1u32, 0u32) + select(arr[2], 1u32, 0u32),
            index,
            cast.x + cast.y + (a << 2u32) + (b >> 1u32),
        );
    }
}
