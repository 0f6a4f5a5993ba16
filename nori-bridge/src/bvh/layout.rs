//! Node layouts of the memory image (docs/memory-format.md, version 2):
//! `nori` (32-byte binary nodes, left child implicit) and the wide layouts
//! with K = 2, 4 or 8 child slots of 32 bytes per node. A slot has the
//! fields of a nori node record, so one record decoder serves both.

use std::fmt;
use std::str::FromStr;

/// The record size every layout is built from: a nori node, or one slot.
pub const RECORD_BYTES: usize = 32;

/// word0 bit 31: the record is a leaf (bits 30..0 = triangle count).
pub const LEAF_BIT: u32 = 1 << 31;

/// word0 of an unused slot of a wide node (every other field is 0).
pub const EMPTY_SLOT: u32 = 1 << 30;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    Nori,
    Wide2,
    Wide4,
    Wide8,
}

impl Layout {
    pub const ALL: [Layout; 4] = [Layout::Nori, Layout::Wide2, Layout::Wide4, Layout::Wide8];

    /// The header's `layout` word: 0 for nori, K for the wide layouts.
    pub fn word(self) -> u32 {
        match self {
            Layout::Nori => 0,
            Layout::Wide2 => 2,
            Layout::Wide4 => 4,
            Layout::Wide8 => 8,
        }
    }

    pub fn from_word(w: u32) -> Option<Layout> {
        Layout::ALL.into_iter().find(|l| l.word() == w)
    }

    /// Embree's maxBranchingFactor for this layout.
    pub fn branching(self) -> u32 {
        match self {
            Layout::Nori => 2,
            wide => wide.word(),
        }
    }

    /// 32-byte records per node: 1 (nori) or K (one per slot).
    pub fn records_per_node(self) -> usize {
        match self {
            Layout::Nori => 1,
            wide => wide.word() as usize,
        }
    }

    /// The header's `nodeBytes`.
    pub fn node_bytes(self) -> usize {
        RECORD_BYTES * self.records_per_node()
    }

    pub fn is_wide(self) -> bool {
        self != Layout::Nori
    }

    /// The `--bvh` value and the scene.json / package.json string.
    pub fn name(self) -> &'static str {
        match self {
            Layout::Nori => "nori",
            Layout::Wide2 => "2",
            Layout::Wide4 => "4",
            Layout::Wide8 => "8",
        }
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Layout {
    type Err = String;
    fn from_str(s: &str) -> Result<Layout, String> {
        Layout::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("BVH layout '{s}' is not one of nori, 2, 4, 8"))
    }
}

/// What a wide node's slot holds, decoded from its word0 / word1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    Leaf { first: u32, count: u32 },
    Inner { node: u32 },
    Empty,
    /// Any other word0: the hardware flags the ray with IndexOverflow.
    Corrupt,
}

impl Slot {
    pub fn decode(word0: u32, word1: u32) -> Slot {
        match word0 {
            w if w & LEAF_BIT != 0 => Slot::Leaf { first: word1, count: w & !LEAF_BIT },
            0 => Slot::Inner { node: word1 },
            EMPTY_SLOT => Slot::Empty,
            _ => Slot::Corrupt,
        }
    }
}
