// Golden: let/let mut, shadowing, assignment and compound assignment, if/else if/else, for
// over ranges (exclusive and inclusive), while, loop, break, continue, return, blocks, `mut`
// parameters, `&mut` in-out helpers, `let _`, and runtime array length.
#[shader_dsl::shader]
pub mod control_flow {
    #[storage(group = 0, binding = 0, read_write)]
    static VALUES: [u32];

    fn bump(counter: &mut u32, by: u32) {
        *counter += by;
        if *counter > 100u32 {
            *counter = 100u32;
        }
    }

    fn twice(counter: &mut u32) {
        bump(counter, 1u32);
        bump(counter, 1u32);
    }

    fn collatz(mut n: u32) -> u32 {
        let mut steps = 0u32;
        while n != 1u32 {
            if n % 2u32 == 0u32 {
                n /= 2u32;
            } else {
                n = 3u32 * n + 1u32;
            }
            steps += 1u32;
            if steps >= 64u32 {
                break;
            }
        }
        steps
    }

    #[compute(workgroup_size(64, 1, 1))]
    pub fn main(#[builtin(global_invocation_id)] gid: UVec3, #[builtin(num_workgroups)] groups: UVec3) {
        let i = gid.x;
        if i >= VALUES.len() {
            return;
        }
        let x = VALUES[i];
        let x = x + groups.x;
        let mut acc = 0u32;
        for k in 0u32..8u32 {
            if k == 3u32 {
                continue;
            } else if k > 6u32 {
                break;
            } else {
                acc += k;
            }
        }
        for k in 1..=4 {
            acc ^= k as u32;
        }
        let mut spins = 0;
        loop {
            spins += 1;
            if spins > 10 {
                break;
            }
        }
        {
            let inner = acc * 2u32;
            acc = inner;
        }
        twice(&mut acc);
        let _ = collatz(x);
        acc <<= 1u32;
        acc >>= 1u32;
        acc |= 1u32;
        acc &= 0xffffu32;
        acc -= 1u32;
        acc *= 3u32;
        acc %= 1000u32;
        VALUES[i] = acc + collatz(x) + (spins as u32);
    }
}
