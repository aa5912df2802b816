//! The one error type of the crate.

use core::fmt;

/// Which caller-provided buffer an [`Error::BufferSize`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Buffer {
    /// Last frame's pixel values: `width * height` entries, row-major.
    Intensities,
    /// Seeds read by a pass: `padded_width * padded_height` entries.
    SeedsIn,
    /// Seeds written by a pass: `padded_width * padded_height` entries.
    SeedsOut,
    /// The dither tile: `tile * tile` ranks.
    DitherTile,
    /// A retarget table: `tile * tile` packed offsets.
    RetargetTable,
    /// A spatiotemporal mask: `2 * width * height * depth` bytes.
    SpatiotemporalMask,
    /// Screen-space sampler keys: `levels * pairs * side * side` keys.
    SampleKeys,
    /// Backward motion vectors: `width * height` pairs.
    Motion,
    /// Reprojection claims (scratch): `padded_width * padded_height` entries.
    Claims,
    /// Per-pixel surface features: `width * height` entries.
    Features,
    /// A pass's scratch buffer: `padded_width * padded_height` entries.
    Scratch,
    /// Weights of a piecewise-constant distribution: `width * height` entries, row-major.
    Weights,
    /// A distribution's CDF table: `1 + height + width * height` entries
    /// ([`Distribution2d::table_len`](crate::distributions::piecewise::Distribution2d::table_len)).
    DistributionTable,
    /// An environment map's linear RGB texels: `width * height` entries, row-major.
    EnvironmentTexels,
    /// One frame's spatiotemporal sequence points: `2 * samples * pairs` words.
    SamplePoints,
    /// The slices of a temporal sorting target: `depth * tile * tile` ranks.
    TemporalSlices,
    /// The slice-to-slice retarget tables of a temporal sorting target:
    /// `depth * tile * tile` packed offsets.
    TemporalTables,
    /// The spatiotemporal sampler's shift-pair tiles: `STEP_COUNT * tile *
    /// tile` words
    /// ([`write_shift_pair_tiles`](crate::sequences::spatiotemporal::write_shift_pair_tiles)).
    ShiftPairTiles,
}

impl fmt::Display for Buffer {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Buffer::Intensities => "intensity buffer",
            Buffer::SeedsIn => "input seed buffer",
            Buffer::SeedsOut => "output seed buffer",
            Buffer::DitherTile => "dither tile",
            Buffer::RetargetTable => "retarget table",
            Buffer::SpatiotemporalMask => "spatiotemporal mask",
            Buffer::SampleKeys => "screen-space sampler keys",
            Buffer::Motion => "motion-vector buffer",
            Buffer::Claims => "reprojection claims buffer",
            Buffer::Features => "surface feature buffer",
            Buffer::Scratch => "scratch seed buffer",
            Buffer::Weights => "distribution weight buffer",
            Buffer::DistributionTable => "distribution table",
            Buffer::EnvironmentTexels => "environment texel buffer",
            Buffer::SamplePoints => "spatiotemporal point table",
            Buffer::TemporalSlices => "temporal target slices",
            Buffer::TemporalTables => "temporal target retarget tables",
            Buffer::ShiftPairTiles => "spatiotemporal shift-pair tiles",
        })
    }
}

/// Everything that can be wrong with the input of a pass. Carries the numbers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Error {
    /// A buffer does not have the length the frame layout requires.
    BufferSize {
        /// Which buffer.
        buffer: Buffer,
        /// Required number of elements.
        expected: usize,
        /// Number of elements passed.
        actual: usize,
    },
    /// Frame width or height is zero, or the padded frame exceeds `u32` indexing.
    FrameSize {
        /// Requested width in pixels.
        width: u32,
        /// Requested height in pixels.
        height: u32,
    },
    /// Block size outside [`MIN_BLOCK`](crate::limits::MIN_BLOCK)`..=`[`MAX_BLOCK`](crate::limits::MAX_BLOCK).
    BlockSize {
        /// Requested block side in pixels.
        block: u32,
    },
    /// Tile side is not a power of two in `2..=`[`MAX_TILE`](crate::limits::MAX_TILE).
    TileSize {
        /// Requested tile side in texels.
        tile: u32,
    },
    /// A retarget-table entry is malformed or moves a texel farther than
    /// [`RETARGET_RADIUS`](crate::limits::RETARGET_RADIUS).
    RetargetOffset {
        /// Row-major texel index in the tile.
        texel: u32,
        /// The packed entry found there.
        packed: u32,
    },
    /// A retarget table is not a permutation of its tile: `texel` receives
    /// `sources` seeds (0 means a seed would be lost, 2 or more duplicated).
    RetargetNotBijective {
        /// Row-major destination texel index in the tile.
        texel: u32,
        /// Number of texels that move there.
        sources: u32,
    },
    /// A spatiotemporal mask side is zero, or a slice has more than 65536
    /// texels (ranks are stored as `u16`).
    MaskSize {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// Depth in slices.
        depth: u32,
    },
    /// A screen-space sampler key layout has a side that is not a power of
    /// two in `1..=`[`MAX_KEY_TILE`](crate::limits::MAX_KEY_TILE), or
    /// no dimension pair, or a number of spp levels outside
    /// `1..=`[`MAX_KEY_LEVELS`](crate::limits::MAX_KEY_LEVELS).
    KeyLayout {
        /// Tile side in pixels.
        side: u32,
        /// Number of dimension pairs.
        pairs: u32,
        /// Number of spp levels.
        levels: u32,
    },
    /// A band of block rows is not `start <= end <= blocks`
    /// ([`permute_frame_rows`](crate::permute_frame_rows)).
    BlockRows {
        /// First block row of the band.
        start: u32,
        /// One past the last block row of the band.
        end: u32,
        /// Block rows of the frame, `ceil(padded_height / block)`.
        blocks: u32,
    },
    /// A piecewise-constant distribution or environment map has a zero side
    /// or a side over [`MAX_DISTRIBUTION_SIDE`](crate::limits::MAX_DISTRIBUTION_SIDE)
    /// (a 1D distribution has `height` 1).
    DistributionSize {
        /// Cells per row.
        width: u32,
        /// Rows.
        height: u32,
    },
    /// A distribution weight is NaN, infinite or negative (for an environment
    /// map the weight is luminance times `sin(theta)`). The value is kept as
    /// its bits (`f32::from_bits`) so the error stays `Eq + Hash`.
    Weight {
        /// Column of the texel.
        x: u32,
        /// Row of the texel (0 for a 1D distribution).
        y: u32,
        /// `f32::to_bits` of the weight found there.
        bits: u32,
    },
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::BufferSize {
                buffer,
                expected,
                actual,
            } => {
                write!(f, "{buffer} has {actual} elements, expected {expected}")
            }
            Error::FrameSize { width, height } => {
                write!(f, "frame size {width}x{height} is empty or too large")
            }
            Error::BlockSize { block } => write!(
                f,
                "block size {block} is outside {}..={}",
                crate::limits::MIN_BLOCK,
                crate::limits::MAX_BLOCK
            ),
            Error::TileSize { tile } => write!(
                f,
                "tile size {tile} is not a power of two in 2..={}",
                crate::limits::MAX_TILE
            ),
            Error::RetargetOffset { texel, packed } => write!(
                f,
                "retarget table entry {packed:#010x} at texel {texel} is malformed or exceeds radius {}",
                crate::limits::RETARGET_RADIUS
            ),
            Error::RetargetNotBijective { texel, sources } => write!(
                f,
                "retarget table is not a permutation: texel {texel} receives {sources} seeds"
            ),
            Error::MaskSize { width, height, depth } => write!(
                f,
                "spatiotemporal mask size {width}x{height}x{depth} has a zero side or more than 65536 texels per slice"
            ),
            Error::KeyLayout { side, pairs, levels } => write!(
                f,
                "sampler key layout {side}x{side}, {pairs} pairs, {levels} spp levels is invalid: the side must be a \
                 power of two up to {}, pairs at least 1, levels 1..={}",
                crate::limits::MAX_KEY_TILE,
                crate::limits::MAX_KEY_LEVELS
            ),
            Error::BlockRows { start, end, blocks } => {
                write!(f, "block rows {start}..{end} are not a band of the frame's {blocks} block rows")
            }
            Error::DistributionSize { width, height } => write!(
                f,
                "distribution size {width}x{height} is invalid: each side must be in 1..={}",
                crate::limits::MAX_DISTRIBUTION_SIDE
            ),
            Error::Weight { x, y, bits } => write!(
                f,
                "weight {} at texel ({x}, {y}) is invalid: weights must be finite and >= 0",
                f32::from_bits(bits)
            ),
        }
    }
}

impl core::error::Error for Error {}
