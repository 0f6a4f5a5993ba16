package rtaccel.study

/** The candidates of the study (docs/dram-traffic.md), each against today's system: 4-wide nodes, a 1 MiB node
  * store and a 256 KiB triangle store (SystemConfig's defaults), 64-byte triangles read one by one, one 64-byte
  * line per hit.
  */
object Candidates {
  private val KiB = 1024L
  private val MiB = 1024 * KiB
  import TriRecords._
  val today: MemoryDesign = MemoryDesign()

  /** The winner's parts together: 4q nodes (the layout), 36-byte triangles read per leaf, hits paired. */
  val compact: MemoryDesign = today.copy(tris = Leaf36, hitBytes = 32)

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
    Candidate("nodes2m", "node store 2 MiB", "4", today.copy(nodeStoreBytes = 2 * MiB)),
    Candidate("tris1m", "node store 1 MiB, triangle store 1 MiB", "4", today.copy(triStoreBytes = MiB)),
    Candidate("4q-nodes2m", "4q, node store 2 MiB", "4q", today.copy(nodeStoreBytes = 2 * MiB)),
    Candidate("compact", "4q + 36 B leaf triangles + paired hits", "4q", compact),
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
    )
  )
}
