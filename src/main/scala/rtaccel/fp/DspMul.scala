package rtaccel.fp

import chisel3._
import chisel3.util._

/** What a product on DSP48E1s ([[DspMul]]) carries from cut to cut: the
  * newest multiplier output `m` (a DSP's M register), the newest sum `p` (its
  * P register) and the low bits of the sums before it, which are final.
  */
class DspPartials(aWidth: Int, bWidth: Int) extends Bundle {
  val m = SInt(DspMul.mWidth(aWidth, bWidth).W)
  val p = SInt(DspMul.pWidth(aWidth, bWidth).W)
  val lo = UInt(DspMul.loWidth(bWidth).W)
}

/** A signed product `a b` built so that Yosys's `xilinx_dsp` packs every
  * DSP48E1 it takes with its input, M and P registers: `a` (at most 25 bits)
  * on the A port, `b` cut into 17-bit unsigned chunks below a signed top chunk
  * of at most 18 bits, one DSP per chunk, each chunk's sum `m_k + (p_{k-1} >>
  * 17)` in its DSP's post-adder over the P cascade. Left to Yosys, a product
  * wider than one DSP (25 x 18) is split with its partial sums between the
  * DSPs in no register (the first DSP of the FP32 multiplier had no register
  * at all), so the estimate, which cuts a DSP48E1 like a register, priced a
  * multiply and its cascade at 0 ns (docs/fmax.md).
  *
  * Stage `s` (1 to [[cuts]]) is followed by a cut: stage k + 1 forms chunk k's
  * product `m_k` (the M register), and stage k + 2 its sum `p_k` (the P
  * register), so chunk k + 1's multiply runs beside chunk k's sum, its
  * operands carried one cut further (Yosys puts that register into AREG and
  * BREG). The operands must come from registers and stay unchanged through
  * the stages (the caller carries them); the value is the same whichever cuts
  * hold a register.
  *
  * An `a` wider than the A port (a format of more than 24 significand bits)
  * is multiplied whole in the first stage and carried through the others:
  * Yosys splits that product as it likes, and the estimate's table says so.
  */
object DspMul {
  private val aBits = 25
  private val bBits = 18
  private val chunk = 17

  def chunks(bWidth: Int): Int = 1 + math.max(0, (bWidth - bBits + chunk - 1) / chunk)

  /** One cut per chunk's multiply and one after the last chunk's sum. */
  def cuts(bWidth: Int): Int = chunks(bWidth) + 1

  private def fits(aWidth: Int): Boolean = aWidth <= aBits
  def mWidth(aWidth: Int, bWidth: Int): Int = if (fits(aWidth)) aWidth + bBits else aWidth + bWidth
  def pWidth(aWidth: Int, bWidth: Int): Int = if (fits(aWidth)) aWidth + bBits + 1 else aWidth + bWidth
  def loWidth(bWidth: Int): Int = math.max(1, chunk * (chunks(bWidth) - 1))

  /** Chunk k of `b`: unsigned 17 bits below the top chunk, the rest signed. */
  private def part(b: SInt, k: Int): SInt = {
    val n = chunks(b.getWidth)
    if (k < n - 1) b.asUInt(chunk * (k + 1) - 1, chunk * k).zext
    else b.asUInt(b.getWidth - 1, chunk * k).asSInt
  }

  /** The partials after stage `s`, from those before it (`prev`, DontCare before stage 1; of the type `new
    * DspPartials(a.getWidth, b.getWidth)` or wider in every field). */
  def step(s: Int, a: SInt, b: SInt, prev: DspPartials): DspPartials = {
    val n = chunks(b.getWidth)
    require(s >= 1 && s <= cuts(b.getWidth), s"DspMul: stage $s of ${cuts(b.getWidth)}")
    // The caller's partials may be wider than this product's (one field serving several products).
    val out = Wire(chiselTypeOf(prev))
    out := prev
    if (!fits(a.getWidth)) {
      out.m := (if (s == 1) a * b else DontCare)
      if (s == 2) out.p := prev.m
      return out
    }
    out.m := (if (s <= n) a * part(b, s - 1) else DontCare)
    if (s >= 2) {
      val k = s - 2
      out.p := (if (k == 0) prev.m else prev.m +& (prev.p >> chunk))
      if (k == 1) out.lo := prev.p.asUInt(chunk - 1, 0)
      else if (k > 1) out.lo := Cat(prev.p.asUInt(chunk - 1, 0), prev.lo(chunk * (k - 1) - 1, 0))
    }
    out
  }

  /** `a b` from the partials after the last stage. */
  def result(a: SInt, b: SInt, last: DspPartials): SInt = {
    val w = a.getWidth + b.getWidth
    val full = if (chunks(b.getWidth) == 1 || !fits(a.getWidth)) last.p.asUInt else Cat(last.p.asUInt, last.lo)
    full(w - 1, 0).asSInt
  }
}
