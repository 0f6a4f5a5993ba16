package rtaccel.formal

import chisel3._
import chisel3.util.experimental.BoringUtils

/** Verification-only access to a unit's inner hardware from a formal monitor,
  * without a port in the shipped design: `Peek(obj, name)` finds the (private)
  * field `name` of an elaborated module by reflection; `Peek.bore(x)` punches
  * ports down to it (BoringUtils.bore), in the formal SystemVerilog only.
  * A renamed field fails the emission with its name, never silently.
  */
object Peek {
  def apply[T](obj: AnyRef, name: String): T = {
    def fields(c: Class[_]): Seq[java.lang.reflect.Field] =
      if (c == null) Nil else c.getDeclaredFields.toSeq ++ fields(c.getSuperclass)
    val f = fields(obj.getClass).find(f => f.getName == name || f.getName.endsWith("$$" + name)).getOrElse(
      throw new IllegalStateException(
        s"Peek: ${obj.getClass.getName} has no field '$name' (renamed? update the formal monitor)"
      )
    )
    f.setAccessible(true)
    f.get(obj).asInstanceOf[T]
  }
  def bore[A <: Data](x: A): A = BoringUtils.bore(x)
}
