package rtaccel.study

/** The candidates of the study (docs/dram-traffic.md), each against today's system: 4-wide nodes, a 1.5 MiB node
  * store and a 256 KiB triangle store (SystemConfig's defaults), 64-byte triangles read one by one, one 64-byte
  * line per hit (the study's unpaired baseline; HitDma pairs them, `hits32`).
  */
object Candidates {
  private val KiB = 1024L
  private val MiB = 1024 * KiB
  import TriRecords._
  val today: MemoryDesign = MemoryDesign()

  /** The winner's parts together: 4q nodes (the layout), 36-byte triangles read per leaf, hits paired; a 1 MiB
    * node store, so that a cache fits beside it and 2 cores. */
  val compact: MemoryDesign = today.copy(nodeStoreBytes = MiB, tris = Leaf36, hitBytes = 32)

  val all: Seq[Candidate] = Seq(
    Candidate("today", "today's system", "4", today),
    Candidate("4q", "4q nodes (64 B)", "4q", today),
    Candidate("8q", "8q nodes (80 B)", "8q", today),
    Candidate("tri48", "triangles: 48 B records", "4", today.copy(tris = Record48)),
    Candidate("leaf48", "triangles: a leaf per read", "4", today.copy(tris = Leaf48)),
    Candidate("leaf36", "triangles: 36 B records, a leaf per read", "4", today.copy(tris = Leaf36)),
    Candidate("hits32", "hits: two per 64 B line", "4", today.copy(hitBytes = 32)),
    Candidate("reorder", "rays reordered, stores only", "4", today, Candidate.Cached(0, reorder = true)),
    Candidate("cache", "LRU cache 1 MiB behind the stores", "4", today, Candidate.Cached(MiB, reorder = false)),
    Candidate("cache-reorder", "LRU cache 1 MiB, rays reordered", "4", today, Candidate.Cached(MiB, reorder = true)),
    Candidate(
      "treelets-dram",
      "treelet queues (256 KiB), queues in DRAM",
      "4",
      today,
      Candidate.TreeletQueues(256 * KiB, inDram = true)
    ),
    Candidate(
      "treelets-chip",
      "treelet queues (256 KiB), queues on chip",
      "4",
      today,
      Candidate.TreeletQueues(256 * KiB, inDram = false)
    ),
    Candidate("nodes1m", "node store 1 MiB", "4", today.copy(nodeStoreBytes = MiB)),
    Candidate("nodes2m", "node store 2 MiB", "4", today.copy(nodeStoreBytes = 2 * MiB)),
    Candidate(
      "tris1m",
      "node store 1 MiB, triangle store 1 MiB",
      "4",
      today.copy(nodeStoreBytes = MiB, triStoreBytes = MiB)
    ),
    Candidate("4q-nodes2m", "4q, node store 2 MiB", "4q", today.copy(nodeStoreBytes = 2 * MiB)),
    Candidate("compact", "4q + 36 B leaf triangles + paired hits, node store 1 MiB", "4q", compact),
    Candidate("compact-nodes2m", "the same, node store 2 MiB", "4q", compact.copy(nodeStoreBytes = 2 * MiB)),
    Candidate(
      "compact-treelets",
      "the same (1 MiB), + treelet queues on chip",
      "4q",
      compact,
      Candidate.TreeletQueues(256 * KiB, inDram = false)
    ),
    Candidate(
      "compact-cache",
      "the same (1 MiB), + LRU cache 1 MiB, reordered",
      "4q",
      compact,
      Candidate.Cached(MiB, reorder = true)
    ),
    Candidate(
      "compact64-nodes2m",
      "4q + 64 B triangles + paired hits, node store 2 MiB",
      "4q",
      compact.copy(tris = Record64, nodeStoreBytes = 2 * MiB)
    ),
    Candidate(
      "compact64-cache",
      "4q + 64 B triangles + paired hits, LRU cache 1 MiB",
      "4q",
      compact.copy(tris = Record64),
      Candidate.Cached(MiB, reorder = false)
    ),
    // Within the block RAM that 2 cores leave (the xc7z045's 545 BRAM36 less the cores' own, make verilog):
    // the stores and the cache resized so that stores, cache and cores fit together.
    Candidate(
      "nodes1280k-tris512k",
      "node store 1.25 MiB, triangle store 512 KiB",
      "4",
      today.copy(nodeStoreBytes = 1280 * KiB, triStoreBytes = 512 * KiB)
    ),
    Candidate(
      "compact64-nodes1536k",
      "4q + 64 B triangles + paired hits, node store 1.5 MiB",
      "4q",
      compact.copy(tris = Record64, nodeStoreBytes = 1536 * KiB)
    ),
    Candidate(
      "compact-cache512k",
      "4q + 36 B leaf triangles + paired hits, node store 1 MiB, LRU cache 512 KiB, reordered",
      "4q",
      compact,
      Candidate.Cached(512 * KiB, reorder = true)
    ),
    Candidate(
      "compact-nodes512k-cache",
      "the same, node store 512 KiB, LRU cache 1 MiB, reordered",
      "4q",
      compact.copy(nodeStoreBytes = 512 * KiB),
      Candidate.Cached(MiB, reorder = true)
    ),
    Candidate(
      "compact64-cache512k",
      "4q + 64 B triangles + paired hits, node store 1 MiB, LRU cache 512 KiB",
      "4q",
      compact.copy(tris = Record64),
      Candidate.Cached(512 * KiB, reorder = false)
    )
  )
}
