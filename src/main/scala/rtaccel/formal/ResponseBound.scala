package rtaccel.formal

import rtaccel.traversal.PrepFetch
import rtaccel.AccelConfig
import rtaccel.bvh.BvhLayout

/** Which scene images a proof allows: assumptions on the node records memory
  * answers with (FormalTop), and the most node and leaf visits they leave a
  * ray, which ResponseBound needs.
  */
sealed trait SceneRule {

  /** (node fetches, leaf visits) a ray can make at most under this rule. */
  def visits(cfg: AccelConfig): (Int, Int)
}

object SceneRule {

  /** An inner child's index is greater than its parent's, as in every image
    * nori-bridge writes (children follow their parent): traversal ends, but a
    * node can be reached along many paths (a DAG), so visits grow fast with
    * the node count; derived here for 2 nodes only.
    */
  case object ChildrenFollow extends SceneRule {
    def visits(cfg: AccelConfig): (Int, Int) = {
      require(cfg.maxNodes == 2, "SceneRule.ChildrenFollow: visits derived for 2 nodes only")
      // Node 1 is the only inner child there can be; with a of the root's K
      // slots naming it, a ray fetches it a times and visits (K - a) + a*K
      // leaves: both grow with a, so a = K is the worst.
      val k = cfg.boxLanes
      (k, k * k)
    }
  }
}

/** The cycles a ray can spend inside RtAccel, from its accept to its hit
  * leaving, derived from the configuration, the datapath latencies and the
  * environment (docs/formal.md walks through each term). Every term is a
  * stage's own latency plus what the other numRayIds - 1 rays can cost it
  * at that stage (each is in one place, so at most n - 1 are ahead of it in
  * any queue, and every shared resource is FIFO or round-robin).
  *
  * p, b, q: prep, box and triangle latencies; L, S, H: memory latency and
  * stall bounds, host stall bound; m: max leaf size.
  */
object ResponseBound {
  final case class Term(name: String, cycles: Int)

  def terms(cfg: AccelConfig, dp: FormalDatapath, env: FormalEnv): Seq[Term] = {
    require(
      cfg.layout.isInstanceOf[BvhLayout.Wide],
      "ResponseBound: derived for the wide layouts (rank stage, 3-cycle control)"
    )
    val (p, b, q) = (dp.prepLatency, dp.boxLatency, dp.primLatency)
    val (l, s, h, m) = (env.memLatency, env.memStall, env.hitStall, cfg.maxLeafSize)
    val others = cfg.numRayIds - 1
    val (fetches, leaves) = env.scene.visits(cfg)
    // Control: rank register, decision + resolve register, then the register
    // between each lane's decision and its queues (`lane`).
    val lane = 1
    val control = 2 + lane
    Seq(
      // accept -> RayPrep p -> InitTraversal queue 2 (a RamQueue's head) -> RayBuffer write 1 ->
      // hand-over (box stage pick) -> atNode 1 -> box b -> control.
      // Others: each ahead in InitTraversal (<= n - 1) takes a cycle, the
      // RayBuffer write port may go to a leaf's tmax first (round-robin: once
      // per write), and node answers take the box stage first (each other
      // ray makes at most `fetches` of them).
      Term("entry", p + 4 + b + control + others * (1 + 1 + fetches) + 1),
      // control out -> Traversal fetch queue 2 -> PrepFetch queue 2 (RamQueues) -> node
      // request (stalled <= S) -> answer <= L -> PrepFetch's registers (1, or 2
      // with the quantized decode stage) -> atNode 1 -> box b -> control.
      // Others: <= n - 1 requests ahead in PrepFetch's queue, each <= S + 1
      // cycles; the two-lane merge costs one cycle per other ray.
      Term(
        s"node fetches ($fetches)",
        fetches * (4 + (s + 1) + l + PrepFetch.latency(cfg) + 1 + b + control + others * (s + 2))
      ),
      // control out -> Traversal leaf queue 2 -> LeafIntersect job queue 2 (RamQueues) ->
      // m requests (each stalled <= S) -> last answer <= L -> register 1 ->
      // triangle q -> exit register 1 -> exit queue 2 -> room for the tmax write (<= 1 lost to a ray entering)
      // -> leaf-return lane 1 -> its lane register. Others: <= n - 1 leaves ahead in the job queue,
      // each issuing m requests (<= S + 1 cycles each) or an empty leaf's
      // exit (1), <= n - 1 exits ahead (<= 2 cycles each), one merge cycle.
      Term(
        s"leaf visits ($leaves)",
        leaves * (4 + m * (s + 1) + l + 1 + q + 3 + 1 + 1 + lane + others * ((m * (s + 1)).max(1) + 2 + 1))
      ),
      // control out -> Traversal done queue 2 (a RamQueue) -> RtAccel's done queue 1 ->
      // output registers 1 -> hit, the host refusing <= H times. Others:
      // <= n - 1 hits ahead (each <= H + 1), one merge cycle.
      Term("exit", 4 + h + others * (h + 2)),
      // The monitor counts the accept cycle and the hit cycle.
      Term("monitor", 1)
    )
  }

  def apply(cfg: AccelConfig, dp: FormalDatapath, env: FormalEnv): Int = terms(cfg, dp, env).map(_.cycles).sum
}
