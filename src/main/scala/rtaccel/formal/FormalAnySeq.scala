package rtaccel.formal

import chisel3._
import chisel3.experimental.IntParam

/** A free value, chosen anew every cycle by the model checker: Yosys's
  * `anyseq`. Formal harnesses only (it has no simulation model); its Verilog
  * is [[FormalAnySeq.verilog]], which EmitFormal writes next to the design.
  */
class FormalAnySeq(width: Int) extends BlackBox(Map("W" -> IntParam(width))) {
  require(width >= 1, s"FormalAnySeq: width must be >= 1, got $width")
  val io = IO(new Bundle { val out = Output(UInt(width.W)) })
}

object FormalAnySeq {

  /** A free value of type `gen`. */
  def apply[T <: Data](gen: T): T = Module(new FormalAnySeq(gen.getWidth)).io.out.asTypeOf(gen)

  val verilog: String =
    """module FormalAnySeq #(parameter W = 1) (output [W-1:0] out);
      |  (* anyseq *) wire [W-1:0] free;
      |  assign out = free;
      |endmodule
      |""".stripMargin
}
