package rtaccel.tools

import org.scalatest.flatspec.AnyFlatSpec

import java.nio.file.Files

/** The committed header, docs page and SystemRDL export are what the generator writes from RegisterMap now. */
class RegMapGenSpec extends AnyFlatSpec {
  behavior of "RegMapGen"

  for ((path, text) <- RegMapGen.outputs)
    it should s"match the committed $path" in {
      assert(Files.exists(path), s"$path is missing: run make regmap")
      assert(Files.readString(path) == text, s"$path differs from what RegMapGen writes: run make regmap")
    }
}
