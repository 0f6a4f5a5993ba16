package rtaccel.tools

import scala.collection.mutable

/** The longest register-to-register path by a [[DelayModel]]'s delay over a
  * flattened Yosys JSON netlist (`synth_xilinx -family xc7`, then `json`):
  * a static timing pass over the mapped cells, one arrival time per net bit,
  * each computed once (so the pass is linear in the netlist's size).
  *
  * Start points (launch at `tcko`): flip-flop (`FD*`) outputs, the module's
  * input ports, and the outputs of cells that cut a path (DSP48E1, block RAM,
  * SRLs, I/O and clock buffers, black boxes, any other cell type without a
  * model here). End points (capture with `setup`, no routed hop: the last
  * cell is packed with its flip-flop): flip-flop data, enable, set and reset
  * inputs, the module's output ports, and the inputs of the cutting cells;
  * clock pins are neither.
  *
  * Arcs through cells, each with the routed hop `net` on the cell's input
  * edge unless that edge stays inside a slice ([[inSlice]]):
  *  - LUT1..LUT6: any input to O, `lut`;
  *  - MUXF7, MUXF8: I0, I1, S to O, `muxf7`, `muxf8`;
  *  - CARRY4, bit by bit (CO[j] reads S and DI up to j, O[j] reads S up to j
  *    and DI below j): S, DI, CYINIT to CO `carryIn`, to O `carryIn +
  *    carryOut`; CI to CO `carryBypass`, to O `carryBypass + carryOut`. Along
  *    a chain this is [[DelayModel.pathNs]]'s sum: the first slice is
  *    entered at S, the next ones at CI, and the last one left at O;
  *  - INV: absorbed into the cell it feeds (no delay, no hop of its own; the
  *    cell it feeds sees the inverter's driver for the slice test);
  *  - distributed RAM (`RAM*` but not `RAMB*`: RAM32M, RAM64M, RAM64X1D, ...):
  *    its read is asynchronous, a LUT reading the address, so each read
  *    address pin reaches its port's data output as a LUT arc (ADDRx to DOx,
  *    A* to SPO or O, DPRA* to DPO); its data outputs also start paths (the
  *    written contents, launched by the write clock at `tcko`), and every
  *    input but the clock (data, write enable, write address) ends one;
  *  - block RAM (`RAMB36E1`, `RAMB18E1`) cuts paths with its own figures: its
  *    data outputs launch at `bramTcko`, or `bramTckoReg` on a port whose
  *    output register is on (`DOA_REG`, `DOB_REG`), and its inputs capture
  *    with `bramSetup`.
  *
  * A DSP48E1 cuts paths whatever its registers, which is honest only for a
  * registered one, so the pass also lists each DSP48E1 that is not
  * ([[unregisteredDsp]]): one whose output is neither its P register (PREG)
  * nor its M register into flip-flops alone, or whose A, B, C or D input is
  * driven through logic with that input's register off.
  */
object TimingGraph {

  /** One net bit along a path: its name, the cell type and pin that drive it, and its arrival time (ns). */
  final case class Step(net: String, driver: String, ns: Double)

  /** The path's cell types from start to end (inverters included), its start and end, its delay, and every net
    * bit along it (`steps`, start first: what [[FmaxPath]] prints). */
  final case class Path(
      cells: Seq[String],
      from: String,
      to: String,
      ns: Double,
      unregisteredDsp: Seq[String] = Nil,
      steps: Seq[Step] = Nil
  )

  private final class Cell(
      val name: String,
      val typ: String,
      val conns: Map[String, Array[Int]],
      val outputs: Set[String],
      val params: Map[String, String]
  )

  /** A parameter's value as Yosys's JSON writes it: a string of binary digits (or a number) for an integer. */
  private def paramInt(v: String): Option[Int] =
    if (v.nonEmpty && v.forall(c => c == '0' || c == '1')) Some(BigInt(v, 2).toInt) else v.toIntOption

  private val lutType = "LUT[1-6]".r

  /** Distributed RAM: a LUT read by its address, written on the clock. */
  def isLutRam(typ: String): Boolean = typ.startsWith("RAM") && !typ.startsWith("RAMB")
  private def isBram(typ: String): Boolean = typ.startsWith("RAMB")
  private def isFlop(typ: String): Boolean = typ.startsWith("FD")
  private def isComb(typ: String): Boolean =
    lutType.matches(typ) || typ == "MUXF7" || typ == "MUXF8" || typ == "CARRY4" || typ == "INV"
  private def isClock(c: Cell, pin: String): Boolean =
    (isFlop(c.typ) && pin == "C") || pin.toUpperCase.contains("CLK")

  private val constant = -1

  /** The longest path of module `top` in the netlist `json` (Yosys `write_json` format). */
  def longest(json: ujson.Value, top: String, model: DelayModel): Path = {
    val mod = json("modules").obj.getOrElse(top, throw new IllegalArgumentException(s"no module $top in the netlist"))
    def bits(v: ujson.Value): Array[Int] = v.arr.iterator.map {
      case ujson.Num(n) => n.toInt
      case _            => constant // "0", "1", "x", "z"
    }.toArray
    val cells = mod("cells").obj.iterator.map { case (name, c) =>
      val dirs = c.obj.get("port_directions").map(_.obj).getOrElse(
        throw new IllegalArgumentException(s"$top: cell $name (${c("type").str}) has no port_directions")
      )
      new Cell(
        name,
        c("type").str,
        c("connections").obj.iterator.map { case (p, v) => p -> bits(v) }.toMap,
        dirs.collect { case (p, d) if d.str == "output" => p }.toSet,
        c.obj.get("parameters").fold(Map.empty[String, String])(_.obj.iterator.map {
          case (k, ujson.Num(x)) => k -> x.toLong.toString
          case (k, x)            => k -> x.str
        }.toMap)
      )
    }.toArray
    val ports = mod("ports").obj.iterator.map { case (p, v) => (p, v("direction").str, bits(v("bits"))) }.toSeq
    val netnames = mod("netnames").obj.iterator.map { case (n, v) =>
      (n, v.obj.get("hide_name").exists(_.num != 0), v.obj.get("offset").fold(0)(_.num.toInt), bits(v("bits")))
    }.toSeq

    val maxBit = (cells.iterator.flatMap(_.conns.valuesIterator.flatMap(_.iterator)) ++
      ports.iterator.flatMap(_._3.iterator) ++ netnames.iterator.flatMap(_._4.iterator)).foldLeft(1)(_ max _)
    val n = maxBit + 1
    // Driver of each bit: a cell's output pin (cell index, port, bit index), or the module's input (-2).
    val drvCell = Array.fill(n)(-1)
    val drvPort = new Array[String](n)
    val drvIdx = new Array[Int](n)
    for ((p, dir, bs) <- ports if dir == "input"; b <- bs if b >= 0) drvCell(b) = -2
    for ((c, ci) <- cells.zipWithIndex; o <- c.outputs; bs <- c.conns.get(o); (b, i) <- bs.zipWithIndex if b >= 0) {
      drvCell(b) = ci; drvPort(b) = o; drvIdx(b) = i
    }

    // A readable name per bit: a public net name if there is one, else the shortest.
    val names = new Array[String](n)
    val public = new Array[Boolean](n)
    for ((nm, hidden, offset, bs) <- netnames; (b, i) <- bs.zipWithIndex if b >= 0) {
      val full = if (bs.length == 1) nm else s"$nm[${offset + i}]"
      val better = names(b) == null || (!hidden && !public(b)) ||
        (hidden == !public(b) && full.length < names(b).length)
      if (better) { names(b) = full; public(b) = !hidden }
    }
    def name(b: Int): String = Option(names(b)).getOrElse(s"bit $b")

    // The cell's arcs into output bit (port, index): (input port, input index, cell delay).
    def arcs(c: Cell, o: String, j: Int): Seq[(String, Int, Double)] = {
      def all(ps: Seq[String], d: Double) =
        ps.flatMap(p => c.conns.get(p).toSeq.flatMap(bs => bs.indices.map(i => (p, i, d))))
      c.typ match {
        case lutType() => all(Seq("I0", "I1", "I2", "I3", "I4", "I5"), model.lut)
        case "MUXF7"   => all(Seq("I0", "I1", "S"), model.muxf7)
        case "MUXF8"   => all(Seq("I0", "I1", "S"), model.muxf8)
        case "INV"     => all(Seq("I"), 0.0)
        case "CARRY4" =>
          val toO = o == "O"
          val out = if (toO) model.carryOut else 0.0
          (0 to j).map(i => ("S", i, model.carryIn + out)) ++
            (0 until (if (toO) j else j + 1)).map(i => ("DI", i, model.carryIn + out)) ++
            Seq(("CYINIT", 0, model.carryIn + out), ("CI", 0, model.carryBypass + out))
        case t if isLutRam(t) =>
          val reads: String => Boolean =
            if (o.startsWith("DO")) _ == "ADDR" + o.drop(2)
            else if (o == "DPO") _.matches("DPRA\\d*")
            else if (o == "SPO" || o == "O") _.matches("A\\d*")
            else _ => false
          all(c.conns.keys.filter(reads).toSeq.sorted, model.lut)
        case _ => Nil
      }
    }
    def bitAt(c: Cell, p: String, i: Int): Int = c.conns.get(p).filter(_.length > i).fold(constant)(_(i))

    // The driver an edge sees for the slice test: inverters are absorbed into the cell they feed.
    def throughInv(b: Int): Int = {
      var x = b
      while (x >= 0 && drvCell(x) >= 0 && cells(drvCell(x)).typ == "INV") x = bitAt(cells(drvCell(x)), "I", 0)
      x
    }

    /** An edge that Vivado routes inside a slice (0 ns in its reports): a LUT into its slice's CARRY4 (S, DI)
      * or MUXF7 (I0, I1), a MUXF7 into its MUXF8 (I0, I1), a CARRY4's CO[3] into the next CARRY4's CI. Every
      * other input (a MUXF's select, a carry's CYINIT, anything from a register or port) takes a routed hop. */
    def inSlice(c: Cell, pin: String, b: Int): Boolean = {
      val d = throughInv(b)
      d >= 0 && drvCell(d) >= 0 && {
        val from = cells(drvCell(d)).typ
        val fromLut = DelayModel.kind(from) == "LUT"
        (c.typ, pin) match {
          case ("CARRY4", "S" | "DI") => fromLut
          case ("MUXF7", "I0" | "I1") => fromLut
          case ("MUXF8", "I0" | "I1") => from == "MUXF7"
          case ("CARRY4", "CI")       => from == "CARRY4" && drvPort(d) == "CO" && drvIdx(d) == 3
          case _                      => false
        }
      }
    }
    def hop(c: Cell, pin: String, b: Int): Double = if (c.typ == "INV" || inSlice(c, pin, b)) 0.0 else model.net

    val arrival = Array.fill(n)(Double.NaN)
    val pred = Array.fill(n)(-1)
    val state = new Array[Byte](n) // 0 unvisited, 1 on the stack, 2 done

    def isStart(b: Int): Boolean = drvCell(b) == -2 || (drvCell(b) >= 0 && {
      val t = cells(drvCell(b)).typ
      !isComb(t) // flip-flops, distributed RAM's written contents, cutting cells
    })
    // A block RAM output leaves its port's output register (`DOx_REG` = 1) or its array, slower than a flip-flop.
    def launch(b: Int): Double = drvCell(b) match {
      case d if d >= 0 && isBram(cells(d).typ) =>
        val reg = if (drvPort(b).startsWith("DOPB") || drvPort(b).startsWith("DOB")) "DOB_REG" else "DOA_REG"
        if (cells(d).params.get(reg).flatMap(paramInt).contains(1)) model.bramTckoReg else model.bramTcko
      case d if d >= 0 && cells(d).typ.startsWith("SRL") => model.srlTcko
      case _                                             => model.tcko
    }
    def inputsOf(b: Int): Array[(Int, Double)] =
      if (drvCell(b) < 0) Array.empty
      else {
        val c = cells(drvCell(b))
        arcs(c, drvPort(b), drvIdx(b)).iterator.map { case (p, i, d) => (bitAt(c, p, i), p, d) }
          .collect { case (ib, p, d) if ib >= 0 => (ib, hop(c, p, ib) + d) }.toArray
      }

    def loop(onStack: Seq[Int], back: Int): Nothing = {
      val cycle = onStack.dropWhile(_ != back) :+ back
      val shown = cycle.map(b => s"${cells(drvCell(b)).name} (${cells(drvCell(b)).typ}) driving ${name(b)}")
      throw new IllegalArgumentException(
        s"$top: combinational loop through cell ${cells(drvCell(back)).name} (${cells(drvCell(back)).typ}): " +
          shown.take(8).mkString(" -> ") + (if (shown.size > 8) " -> ..." else "")
      )
    }

    // Depth-first, iteratively (a carry chain of a wide adder is thousands of bits deep).
    val stackBits = mutable.ArrayBuffer.empty[Int]
    val stackIns = mutable.ArrayBuffer.empty[Array[(Int, Double)]]
    val stackPos = mutable.ArrayBuffer.empty[Int]
    def push(b: Int): Unit = { state(b) = 1; stackBits += b; stackIns += inputsOf(b); stackPos += 0 }
    def visit(root: Int): Double = {
      if (state(root) == 0) {
        push(root)
        while (stackBits.nonEmpty) {
          val top = stackBits.size - 1
          val ins = stackIns(top)
          val pos = stackPos(top)
          if (pos < ins.length) {
            stackPos(top) = pos + 1
            val ib = ins(pos)._1
            if (state(ib) == 0) push(ib)
            else if (state(ib) == 1) loop(stackBits.toSeq, ib)
          } else {
            val b = stackBits(top)
            var best = if (isStart(b)) launch(b) else Double.NegativeInfinity
            var from = -1
            for ((ib, d) <- ins) {
              val t = arrival(ib) + d
              if (t > best) { best = t; from = ib }
            }
            arrival(b) = best; pred(b) = from; state(b) = 2
            stackBits.remove(top); stackIns.remove(top); stackPos.remove(top)
          }
        }
      }
      arrival(root)
    }

    var worst = Double.NegativeInfinity
    var worstBit = -1
    var worstTo = ""
    def end(b: Int, label: => String, setup: Double = model.setup): Unit = if (b >= 0) {
      val t = visit(b) + setup
      if (t > worst) { worst = t; worstBit = b; worstTo = label }
    }
    for ((p, dir, bs) <- ports if dir == "output"; (b, i) <- bs.zipWithIndex)
      end(b, if (bs.length == 1) p else s"$p[$i]")
    for (c <- cells if !isComb(c.typ); (p, bs) <- c.conns if !c.outputs.contains(p) && !isClock(c, p)) {
      // Named after the register it loads (its Q net), else after the net and the cell's pin.
      def label(i: Int) =
        if (isFlop(c.typ)) bitAt(c, "Q", 0) match {
          case q if q >= 0 => name(q) + (if (p == "D") "" else s" ($p)")
          case _           => s"${name(bs(i))} (${c.typ}.$p)"
        }
        else if (c.typ == "OBUF") name(bitAt(c, "O", 0)) // the output port
        else s"${name(bs(i))} (${c.typ}.$p)"
      for ((b, i) <- bs.zipWithIndex) end(b, label(i), if (isBram(c.typ)) model.bramSetup else model.setup)
    }
    require(worstBit >= 0, s"$top: no register-to-register path in the netlist")

    // Each DSP48E1 that the pass cuts without its registers (a multiply in the same cycle as fabric logic).
    val users = new Array[List[(Int, String)]](n)
    for ((c, ci) <- cells.zipWithIndex; (p, bs) <- c.conns if !c.outputs.contains(p); b <- bs if b >= 0)
      users(b) = (ci, p) :: Option(users(b)).getOrElse(Nil)
    val outBits = ports.collect { case (_, "output", bs) => bs.toSeq }.flatten.toSet
    def isLogic(b: Int): Boolean = {
      val d = throughInv(b)
      d >= 0 && drvCell(d) >= 0 && {
        val t = cells(drvCell(d)).typ
        isComb(t) || isLutRam(t)
      }
    }
    val unregisteredDsp = cells.toSeq.filter(_.typ == "DSP48E1").flatMap { c =>
      def reg(p: String) = c.params.get(p).flatMap(paramInt).getOrElse(0)
      def driven(p: String) = c.conns.get(p).toSeq.flatMap(_.toSeq).filter(_ >= 0)
      val outs = driven("P").toSet.flatMap((b: Int) => Option(users(b)).getOrElse(Nil))
      val pcout = driven("PCOUT").exists(b => Option(users(b)).exists(_.nonEmpty))
      val intoLogic = pcout || driven("P").exists(outBits) || outs.exists { case (ci, p) =>
        !(isFlop(cells(ci).typ) && p == "D")
      }
      val why = Seq(
        Option.when(reg("PREG") == 0 && reg("MREG") == 0)("no M or P register"),
        Option.when(reg("PREG") == 0 && reg("MREG") != 0 && intoLogic)("no P register, P into logic"),
        Seq(("A", "AREG"), ("B", "BREG"), ("C", "CREG"), ("D", "DREG")).collectFirst {
          case (pin, r) if reg(r) == 0 && driven(pin).exists(isLogic) => s"$pin through logic without $r"
        }
      ).flatten
      Option.when(why.nonEmpty) {
        val regs = Seq("AREG", "BREG", "MREG", "PREG").map(r => s"$r=${reg(r)}").mkString(" ")
        s"${c.name} ($regs: ${why.mkString(", ")})"
      }
    }

    val chain = Iterator.iterate(worstBit)(pred(_)).takeWhile(_ >= 0).toSeq.reverse
    val start = chain.head
    val from = drvCell(start) match {
      case c if c >= 0 && cells(c).typ == "IBUF" => name(bitAt(cells(c), "I", 0)) // the input port
      case c if c >= 0 && !isFlop(cells(c).typ)  => s"${name(start)} (${cells(c).typ}.${drvPort(start)})"
      case _                                     => name(start)
    }
    val steps = chain.map { b =>
      val driver = drvCell(b) match {
        case c if c >= 0 => s"${cells(c).typ}.${drvPort(b)}"
        case _           => "input"
      }
      Step(name(b), driver, arrival(b))
    }
    Path(chain.drop(1).map(b => cells(drvCell(b)).typ), from, worstTo, worst, unregisteredDsp, steps)
  }
}
