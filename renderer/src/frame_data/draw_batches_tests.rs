//! The batch layout: grouping, spare slots, and placing draws in place.

use super::*;

fn opaque() -> DrawPlace {
    DrawPlace::Batch((false, false, false, 0))
}

#[test]
fn batches_group_by_pipeline_and_keep_scene_order_inside() {
    let places = [
        opaque(),
        DrawPlace::Blended,
        DrawPlace::Batch((true, true, false, 0)),
        opaque(),
        opaque(),
        DrawPlace::Batch((false, false, true, 0)),
        DrawPlace::Blended,
        opaque(),
        DrawPlace::Hidden,
    ];
    let layout = BatchLayout::from_places(places.into_iter());
    let batches: Vec<(BatchKey, u32, u32)> = layout
        .batches
        .iter()
        .map(|b| (b.key(), b.first_slot, b.slot_count))
        .collect();
    // Each batch: its draws, then two spare slots.
    assert_eq!(
        batches,
        [
            ((false, false, false, 0), 0, 6),
            ((false, false, true, 0), 6, 3),
            ((true, true, false, 0), 9, 3),
        ]
    );
    let n = NO_DRAW;
    assert_eq!(layout.slot_draws, [0, 3, 4, 7, n, n, 5, n, n, 2, n, n]);
    assert_eq!(layout.blended, [1, 6]);
    assert_eq!(layout.slot_of(8), None, "a hidden draw has no slot");
    assert_eq!(layout.slot_of(7), Some(3));
    assert_eq!(layout.draw_count(), 6);
}

/// Places draws at random and checks the layout against a plain list of where each draw
/// should be: every batched draw in exactly one slot of its key's batch, no other slot
/// holding it, the blended list exactly the blended draws, ascending, and the slots `place`
/// reports exactly those that changed.
#[test]
fn material_programs_split_batches_after_gltf_ones() {
    let custom = DrawPlace::Batch((false, false, false, 2));
    let places = [
        custom,
        opaque(),
        DrawPlace::Batch((false, false, false, 1)),
        custom,
    ];
    let layout = BatchLayout::from_places(places.into_iter());
    let batches: Vec<(u32, Vec<u32>)> = layout
        .batches
        .iter()
        .map(|b| {
            let slots = b.slots().map(|s| layout.slot_draws[s as usize]);
            (b.program, slots.filter(|&d| d != NO_DRAW).collect())
        })
        .collect();
    assert_eq!(batches, [(0, vec![1]), (1, vec![2]), (2, vec![0, 3])]);
}

#[test]
fn placing_keeps_every_draw_in_one_slot_of_its_batch() {
    let keys = [
        opaque(),
        DrawPlace::Batch((false, true, false, 0)),
        DrawPlace::Batch((false, false, true, 0)),
    ];
    let mut seed = 0x2545_f491_u64;
    let mut next = |n: u64| {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((seed >> 33) % n) as usize
    };
    let mut expected: Vec<DrawPlace> = (0..40).map(|i| keys[i % 3]).collect();
    let mut layout = BatchLayout::from_places(expected.iter().copied());
    let (mut in_place, mut rebuilt) = (0, 0);
    for _ in 0..2000 {
        let d = next(60);
        let place = match next(5) {
            0 => DrawPlace::Hidden,
            1 => DrawPlace::Blended,
            k => keys[k - 2],
        };
        if d >= expected.len() {
            expected.resize(d + 1, DrawPlace::Hidden);
        }
        expected[d] = place;
        let before = layout.clone();
        match layout.place(d as u32, place) {
            Ok(changed) => {
                in_place += 1;
                let slots = before.slot_draws.iter().zip(&layout.slot_draws);
                for (slot, (a, b)) in slots.enumerate() {
                    assert_eq!(a != b, changed.contains(&(slot as u32)), "slot {slot}");
                }
            }
            Err(NoRoom) => {
                assert_eq!(layout, before, "a refused place changes nothing");
                rebuilt += 1;
                layout = BatchLayout::from_places(expected.iter().copied());
            }
        }
        for (d, want) in expected.iter().enumerate() {
            let d32 = d as u32;
            if let DrawPlace::Batch(key) = *want {
                let slot = layout.slot_of(d32).expect("a batched draw has a slot");
                assert_eq!(layout.slot_draws[slot as usize], d32);
                let batch = layout.batches.iter().find(|b| b.slots().contains(&slot));
                assert_eq!(batch.map(DrawBatch::key), Some(key));
            } else {
                assert_eq!(layout.slot_of(d32), None);
            }
            let in_slots = layout.slot_draws.iter().filter(|&&s| s == d32).count();
            let batched = matches!(want, DrawPlace::Batch(_));
            assert_eq!(
                in_slots,
                usize::from(batched),
                "draw {d} in {in_slots} slots"
            );
        }
        let batched = expected
            .iter()
            .filter(|p| matches!(p, DrawPlace::Batch(_)))
            .count();
        assert_eq!(layout.draw_count() as usize, batched);
        let blended: Vec<u32> = (0..expected.len() as u32)
            .filter(|&d| expected[d as usize] == DrawPlace::Blended)
            .collect();
        assert_eq!(layout.blended, blended);
    }
    assert!(
        in_place > 1000 && rebuilt > 10,
        "{in_place} placed in place, {rebuilt} rebuilt"
    );
}
