//! Issue 18: every instruction set of the CPU permutation (portable, AVX2,
//! AVX-512; each where this CPU has it) and every split of a frame into
//! bands of block rows (`permute_frame_rows`, and `permute_frame_par` on a
//! rayon pool) give, bit for bit, the output of the reference two-pass form
//! (`sort_frame` then `retarget_frame`) for arbitrary frame sizes, all block
//! sizes, tiles 2..128 (the fast path covers 16..128) and intensities with
//! NaN, infinities, signed zeros and ties.

use conformance::fixtures::{random_table, random_tile};
use conformance::permute_par::permute_frame_par;
use proptest::prelude::*;
use sampler_core::*;

/// Intensities mixing ordinary values, ties and every special f32.
fn intensity() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => (0u32..8).prop_map(|i| i as f32 * 0.25), // many ties
        4 => any::<f32>(),                             // NaN payloads, subnormals, both signs
        1 => Just(f32::NAN),
        1 => Just(-f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(f32::NEG_INFINITY),
        1 => Just(-0.0f32),
        1 => Just(0.0f32),
    ]
}

/// One frame's inputs and the reference output.
struct Frame {
    layout: FrameLayout,
    frame: u32,
    intensities: Vec<f32>,
    tile_values: Vec<u32>,
    packed: Vec<Vec<u32>>,
    seeds: Vec<u32>,
}

impl Frame {
    fn new(layout: FrameLayout, frame: u32, salt: u32, intensities: Vec<f32>) -> Frame {
        let tile = layout.tile();
        Frame {
            layout,
            frame,
            intensities,
            tile_values: random_tile(tile, salt, salt.is_multiple_of(3)),
            packed: (0..STEP_COUNT as u32)
                .map(|i| random_table(tile, salt.wrapping_add(i), 300))
                .collect(),
            seeds: (0..layout.seed_count() as u32)
                .map(|i| sequences::seed::hash_u32(i ^ salt))
                .collect(),
        }
    }

    fn tile(&self) -> DitherTile<'_> {
        DitherTile::new(self.layout.tile(), &self.tile_values).unwrap()
    }

    fn tables(&self) -> RetargetTables<'_> {
        let p = &self.packed;
        RetargetTables::new(self.layout.tile(), [&p[0], &p[1], &p[2], &p[3]]).unwrap()
    }

    /// `sort_frame` then `retarget_frame`: the per-block reference.
    fn reference(&self) -> Vec<u32> {
        let (mut mid, mut out) = (vec![0; self.seeds.len()], vec![0; self.seeds.len()]);
        sort_frame(
            &self.layout,
            self.frame,
            &self.intensities,
            &self.tile(),
            &self.seeds,
            &mut mid,
        )
        .unwrap();
        retarget_frame(&self.layout, self.frame, &self.tables(), &mid, &mut out).unwrap();
        out
    }

    /// The frame permuted with `isa` in bands cut at `cuts` (block rows,
    /// any order, clamped to the frame), each band into its own slice.
    fn banded(&self, isa: Isa, cuts: &[u32]) -> Vec<u32> {
        let blocks = self.layout.params(self.frame).blocks_y();
        let mut bounds: Vec<u32> = cuts.iter().map(|&c| c % (blocks + 1)).collect();
        bounds.extend([0, blocks]);
        bounds.sort_unstable();
        let mut out = vec![u32::MAX; self.seeds.len()];
        for pair in bounds.windows(2) {
            let rows = pair[0]..pair[1];
            let slice = &mut out[band_seed_range(&self.layout, rows.clone())];
            let (tile, tables) = (self.tile(), self.tables());
            permute_frame_rows_isa(
                isa,
                &self.layout,
                self.frame,
                &self.intensities,
                &tile,
                &tables,
                &self.seeds,
                rows,
                slice,
            )
            .unwrap();
        }
        out
    }
}

/// The instruction sets this CPU can run (the others are reported once).
fn isas() -> Vec<Isa> {
    Isa::ALL.into_iter().filter(|isa| isa.is_available()).collect()
}

#[test]
fn instruction_sets_under_test() {
    assert!(Isa::Baseline.is_available());
    for isa in Isa::ALL {
        if !isa.is_available() {
            eprintln!(
                "skipped {isa:?} in this file's tests: this CPU or OS lacks it (best here: {:?})",
                Isa::best()
            );
        }
    }
    assert_eq!(isas().last(), Some(&Isa::best()));
}

/// A frame size, block, tile, frame number, salt and its intensities.
fn case() -> impl Strategy<Value = (FrameLayout, u32, u32, Vec<f32>)> {
    (
        1u32..=150,
        1u32..=70,
        MIN_BLOCK..=MAX_BLOCK,
        1u32..=7,
        any::<u32>(),
        any::<u32>(),
    )
        .prop_flat_map(|(width, height, block, tile_log2, frame, salt)| {
            let layout = FrameLayout::new(width, height, block, 1 << tile_log2).unwrap();
            prop::collection::vec(intensity(), layout.pixel_count())
                .prop_map(move |intensities| (layout, frame, salt, intensities))
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn every_isa_and_band_split_equals_the_reference(
        (layout, frame, salt, intensities) in case(),
        cuts in prop::collection::vec(any::<u32>(), 0..5),
    ) {
        let f = Frame::new(layout, frame, salt, intensities);
        let want = f.reference();
        let mut whole = vec![0; f.seeds.len()];
        permute_frame(&f.layout, frame, &f.intensities, &f.tile(), &f.tables(), &f.seeds, &mut whole).unwrap();
        prop_assert!(whole == want, "permute_frame");
        for isa in isas() {
            prop_assert!(f.banded(isa, &[]) == want, "{:?}, whole frame", isa);
            prop_assert!(f.banded(isa, &cuts) == want, "{:?}, cuts {:?}", isa, cuts);
        }
    }
}

/// Frames wide enough for every lane group width, odd sizes, the fast
/// path's tiles and all its block sizes; bands of one block row, uneven
/// bands, and the rayon convenience.
#[test]
fn large_odd_frames_equal_the_reference_for_every_isa_and_split() {
    let mut state = 0x5eed_u32;
    let mut next = move || {
        state = sequences::seed::hash_u32(state);
        state
    };
    // 3600 wide: past one ring for every block size and tile, so two
    // column strips.
    for (width, height) in [(517u32, 93u32), (130, 301), (3600, 21)] {
        for block in [2u32, 4, 8] {
            for tile in [16u32, 64, 128] {
                let layout = FrameLayout::new(width, height, block, tile).unwrap();
                let intensities: Vec<f32> = (0..layout.pixel_count())
                    .map(|_| match next() % 8 {
                        0 => f32::NAN,
                        1 => f32::NEG_INFINITY,
                        2 => f32::INFINITY,
                        3 | 4 => (next() % 4) as f32, // ties
                        _ => f32::from_bits(next()),
                    })
                    .collect();
                let f = Frame::new(layout, next() % 1000, next(), intensities);
                let want = f.reference();
                let blocks = layout.params(f.frame).blocks_y();
                let every_row: Vec<u32> = (1..blocks).collect();
                for isa in isas() {
                    let what = format!("{isa:?}, {width}x{height}, block {block}, tile {tile}");
                    assert!(f.banded(isa, &[]) == want, "{what}, whole frame");
                    assert!(
                        f.banded(isa, &[1, 2, blocks / 3, blocks - 1]) == want,
                        "{what}, uneven bands"
                    );
                    if tile == 16 {
                        // Each band fills the per-frame cache again: cheap for small tiles only.
                        assert!(
                            f.banded(isa, &every_row) == want,
                            "{what}, one block row per band"
                        );
                    }
                    for bands in [2u32, 3] {
                        let mut out = vec![0; f.seeds.len()];
                        let (i, tile, tables) = (&f.intensities, f.tile(), f.tables());
                        permute_frame_par(
                            isa, &layout, f.frame, i, &tile, &tables, &f.seeds, &mut out, bands,
                        )
                        .unwrap();
                        assert!(out == want, "{what}, permute_frame_par with {bands} bands");
                    }
                }
            }
        }
    }
}
