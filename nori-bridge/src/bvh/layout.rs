//! Node layouts of the memory image (docs/memory-format.md, version 2):
//! `nori` (32-byte binary nodes, left child implicit) and the wide layouts
//! with K = 2, 4 or 8 child slots of 32 bytes per node. A slot has the
//! fields of a nori node record, so one record decoder serves both.
//! `4q` / `8q`: wide nodes with quantized child boxes (bvh/quant.rs); in
//! memory they are decoded into the same K slot records (word0, word1, the
//! decoded box), so the walks and checks serve them unchanged.

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
    /// 4-wide, child boxes quantized to 8 bits per plane (64-byte nodes).
    Quant4,
    /// 8-wide, child boxes quantized to 8 bits per plane (80-byte nodes).
    Quant8,
}

impl Layout {
    pub const ALL: [Layout; 6] = [
        Layout::Nori,
        Layout::Wide2,
        Layout::Wide4,
        Layout::Wide8,
        Layout::Quant4,
        Layout::Quant8,
    ];

    /// The header's `layout` word: 0 for nori, K for the wide layouts,
    /// 16 + K for the quantized ones (20 = 4q, 24 = 8q).
    pub fn word(self) -> u32 {
        match self {
            Layout::Nori => 0,
            Layout::Wide2 => 2,
            Layout::Wide4 => 4,
            Layout::Wide8 => 8,
            Layout::Quant4 => 20,
            Layout::Quant8 => 24,
        }
    }

    /// Child slots per node (1 for nori).
    pub fn k(self) -> u32 {
        match self {
            Layout::Nori => 1,
            Layout::Quant4 => 4,
            Layout::Quant8 => 8,
            wide => wide.word(),
        }
    }

    /// Child boxes stored quantized relative to the node (4q, 8q).
    pub fn is_quant(self) -> bool {
        matches!(self, Layout::Quant4 | Layout::Quant8)
    }

    pub fn from_word(w: u32) -> Option<Layout> {
        Layout::ALL.into_iter().find(|l| l.word() == w)
    }

    /// Embree's maxBranchingFactor for this layout.
    pub fn branching(self) -> u32 {
        match self {
            Layout::Nori => 2,
            wide => wide.k(),
        }
    }

    /// Records per node in memory (Image::nodes): 1 (nori) or K (one per
    /// slot; a quantized node is decoded into K slot records).
    pub fn records_per_node(self) -> usize {
        self.k() as usize
    }

    /// The header's `nodeBytes`: 32 K, or for the quantized layouts 64 (4q)
    /// and 80 (8q) (docs/memory-format.md).
    pub fn node_bytes(self) -> usize {
        match self {
            Layout::Quant4 => 64,
            Layout::Quant8 => 80,
            _ => RECORD_BYTES * self.records_per_node(),
        }
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
            Layout::Quant4 => "4q",
            Layout::Quant8 => "8q",
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
            .ok_or_else(|| format!("BVH layout '{s}' is not one of nori, 2, 4, 8, 4q, 8q"))
    }
}

/// What a wide node's slot holds, decoded from its word0 / word1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    Leaf {
        first: u32,
        count: u32,
    },
    Inner {
        node: u32,
    },
    Empty,
    /// Any other word0: the hardware flags the ray with IndexOverflow.
    Corrupt,
}

impl Slot {
    pub fn decode(word0: u32, word1: u32) -> Slot {
        match word0 {
            w if w & LEAF_BIT != 0 => Slot::Leaf {
                first: word1,
                count: w & !LEAF_BIT,
            },
            0 => Slot::Inner { node: word1 },
            EMPTY_SLOT => Slot::Empty,
            _ => Slot::Corrupt,
        }
    }
}
