package rtaccel.regress

/** The command-line entry points' error rule: a bad option or input is an
  * IllegalArgumentException, printed as `Error: <message>` with exit code 2.
  */
object Cli {
  def orExit[A](body: => A): A =
    try body
    catch {
      case e: IllegalArgumentException =>
        System.err.println(s"Error: ${e.getMessage}")
        sys.exit(2)
    }
}
