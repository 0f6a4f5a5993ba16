package rtaccel.datapath

import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._

/** One line of a kernel vector file (docs/kernels.md section 7): its family,
  * the input tokens and, in `.out` files, the output tokens after `:`.
  * Every token is an FP32 bit pattern (or a 0/1 flag or axis digit, which
  * read the same in hex).
  */
final case class KernelCase(file: String, line: Int, family: String, in: IndexedSeq[BigInt], out: IndexedSeq[BigInt]) {
  def where: String = s"$file:$line ($family)"
  def o: Seq[BigInt] = in.slice(0, 3)
  def d: Seq[BigInt] = in.slice(3, 6)
  def tmin: BigInt = in(6)
  def tmax: BigInt = in(7)

  /** Box files: bmin, bmax. */
  def bmin: Seq[BigInt] = in.slice(8, 11)
  def bmax: Seq[BigInt] = in.slice(11, 14)

  /** Triangle files: the nine vertex words p0, p1, p2. */
  def verts: Seq[BigInt] = in.slice(8, 17)
}

object KernelVectors {
  val root: Path = Paths.get(sys.props.getOrElse("rtaccel.root", "."))
  val outDir: Path = root.resolve("hls/build/vectors")
  val hardDir: Path = root.resolve("testdata/kernels")

  /** Input-token and output-token counts per file kind. */
  val bboxIn = 14; val bboxOutIn = 17; val bboxOut = 3
  val triIn = 17; val wtOutIn = 23; val primOut = 5

  private val Family = "[a-z0-9_]+".r
  private val Hex = "[0-9a-fA-F]{1,8}".r

  /** Reads a vector file; any malformed line fails naming file, line and token. */
  def read(path: Path, inCount: Int, outCount: Int): IndexedSeq[KernelCase] = {
    if (!Files.exists(path)) {
      val hint = if (path.toString.contains("hls/build")) "run `make -C hls vectors` first (make test does)"
      else "it is committed; check out testdata/"
      throw new java.io.FileNotFoundException(s"$path is missing: $hint")
    }
    val name = path.toString
    Files.readAllLines(path).asScala.toIndexedSeq.zipWithIndex.flatMap { case (raw, i) =>
      val line = raw.takeWhile(_ != '#').trim
      if (line.isEmpty) None
      else {
        def bad(msg: String) = throw new IllegalArgumentException(s"$name:${i + 1}: $msg")
        val (inPart, outPart) = line.split(":", -1) match {
          case Array(a)    => (a, "")
          case Array(a, b) => (a, b)
          case _           => bad("more than one ':'")
        }
        val toks = inPart.trim.split("\\s+").toIndexedSeq
        val fam = toks.head
        if (!Family.matches(fam)) bad(s"bad family '$fam'")
        def hex(t: String) = if (Hex.matches(t)) BigInt(t, 16) else bad(s"bad value token '$t'")
        val in = toks.tail.map(hex)
        val out = outPart.trim.split("\\s+").toIndexedSeq.filter(_.nonEmpty).map(hex)
        if (in.size != inCount) bad(s"expected $inCount input values, got ${in.size}")
        if (out.size != outCount) bad(s"expected $outCount output values, got ${out.size}")
        Some(KernelCase(name, i + 1, fam, in, out))
      }
    }
  }

  def bboxOutFile: IndexedSeq[KernelCase] = read(outDir.resolve("bbox.out"), bboxOutIn, bboxOut)
  def mtOutFile: IndexedSeq[KernelCase] = read(outDir.resolve("prim_mt.out"), triIn, primOut)
  def wtOutFile: IndexedSeq[KernelCase] = read(outDir.resolve("prim_wt.out"), wtOutIn, primOut)
  def bboxHard: IndexedSeq[KernelCase] = read(hardDir.resolve("bbox_hard.txt"), bboxIn, 0)
  def triHard: IndexedSeq[KernelCase] = read(hardDir.resolve("tri_hard.txt"), triIn, 0)

  def hex(x: BigInt): String = f"${x.toLong}%08x"
}
