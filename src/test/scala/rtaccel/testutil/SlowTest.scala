package rtaccel.testutil

import org.scalatest.Tag

/** Tags a check too slow for `make test` that another check there already covers in part: `make test` runs
  * the specs without it (`-l rtaccel.SlowTest`), `make test-slow` runs only the tagged ones. Each tagged test
  * says in a comment what in `make test` covers its ground.
  */
object SlowTest extends Tag("rtaccel.SlowTest")
