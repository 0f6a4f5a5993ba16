package rtaccel.formal

import scala.util.matching.Regex

/** Makes firtool 1.62's SystemVerilog readable by Yosys 0.23's `read_verilog -formal`.
  *
  * Chisel 6 lowers `chisel3.assert` to an if-else-fatal block under
  * `ifndef SYNTHESIS`:
  * {{{
  *   if (~reset & bad) begin
  *     if (`ASSERT_VERBOSE_COND_) $error("Assertion failed: <name>: ...");
  *     if (`STOP_COND_) $fatal;
  *   end
  * }}}
  * which simulators stop on but Yosys cannot read (no `$error`). Each
  * `$error` becomes `<name>: assert(1'b0);` under the same condition, so the
  * model checker proves `bad` never holds; `$fatal` and the `$fwrite` of
  * failed-assumption messages (the `assume` itself is emitted separately)
  * are dropped. Names repeat when one Scala line asserts in a loop, so each
  * gets a `_<n>` suffix, in file order.
  */
object ForYosys {
  private val str = "\"(?:[^\"\\\\]|\\\\.)*\""
  private val error: Regex =
    ("""\$error\("Assertion failed: ([A-Za-z_][A-Za-z_0-9]*)""" + "(?:[^\"\\\\]|\\\\.)*\"\\);").r
  private val fatal: Regex = """\$fatal;""".r
  private val fwrite: Regex = ("""\$fwrite\(32'h[0-9a-fA-F]+,\s*""" + str + """\);""").r

  def apply(sv: String): String = {
    val seen = scala.collection.mutable.Map[String, Int]().withDefaultValue(0)
    val asserts = error.replaceAllIn(
      sv,
      m => {
        val name = m.group(1)
        seen(name) += 1
        Regex.quoteReplacement(s"${name}_${seen(name)}: assert(1'b0);")
      }
    )
    require(!asserts.contains("$error"), "ForYosys: an $error without an 'Assertion failed: <name>:' message")
    fwrite.replaceAllIn(fatal.replaceAllIn(asserts, ";"), ";")
  }

  /** The property names in a converted file, in order. */
  def names(sv: String): Seq[String] =
    """([A-Za-z_][A-Za-z_0-9]*): assert\(1'b0\);""".r.findAllMatchIn(sv).map(_.group(1)).toSeq
}
