//! front.json of a tiled run: the run's header as for an untiled run, and in place of a kept
//! list per member, the tiled front: every tile's kept sets and each member's choice of one
//! per tile. A tile's kept sets are packed as an untiled front's are
//! ([`crate::kept_codec::PackedSet`]: `kept_packed`, or `kept_diff` with the tile's member
//! before it); readers also take the plain index arrays of older files.
//!
//! ```json
//! {"grid":{…},"algorithm":"memetic","params":{…},"seed":1,"evaluations":…,"millis":…,
//!  "tiled":{"plan":{…},"tiles":[{"index":0,"borders":{…},
//!           "members":[{"kept_packed":"AAUBpgI="},{"kept_diff":"GAE="},…],
//!           "candidates":[{"member":0,"level":3,"e_tile":…,"e_share":…,"e_max":…,"t":…},…]},…],
//!           "members":[{"E_sum":…,"E_max":…,"T":…,"level":3,"choice":[…]},…]}}
//! ```

use super::TiledFront;
use crate::front_file::RunHeader;
use serde::{Deserialize, Serialize};

/// The whole file of a tiled run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TiledFrontFile {
    /// The whole grid, the method as every tile ran it ([`tile_config`](super::tile_config)),
    /// the run's seed and its cost over all tiles.
    #[serde(flatten)]
    pub header: RunHeader,
    /// Threads the tiles ran on (the front does not depend on it).
    pub threads: usize,
    /// The tiles' fronts and the whole-grid members.
    pub tiled: TiledFront,
}
