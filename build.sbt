// rtaccel: a Chisel generator for a BVH-traversal and ray/triangle-intersection accelerator.
ThisBuild / scalaVersion := "2.13.15"
ThisBuild / organization := "rtaccel"
ThisBuild / version := "0.1.0"

val chiselVersion = "6.7.0"

lazy val root = (project in file("."))
  .settings(
    name := "rtaccel",
    libraryDependencies ++= Seq(
      "org.chipsalliance" %% "chisel" % chiselVersion,
      "com.lihaoyi" %% "ujson" % "3.1.0",
      "edu.berkeley.cs" %% "chiseltest" % "6.0.0",
      "org.scalatest" %% "scalatest" % "3.2.19" % Test
    ),
    addCompilerPlugin("org.chipsalliance" % "chisel-plugin" % chiselVersion cross CrossVersion.full),
    scalacOptions ++= Seq("-deprecation", "-feature", "-unchecked", "-language:reflectiveCalls", "-Ymacro-annotations"),
    // Tests run in a forked JVM: Chisel/firtool need a deep stack, Verilator
    // builds keep their own processes, and a crash cannot take sbt down.
    Test / fork := true,
    Test / javaOptions ++= Seq("-Xss8m", "-Xmx4g"),
    Test / testOptions += Tests.Argument(TestFrameworks.ScalaTest, "-oD"),
    // The flows (`make regress`, `make bench`, ...) are Scala mains in src/main
    // that drive chiseltest, hence chiseltest in Compile scope; they fork too.
    run / fork := true,
    run / javaOptions ++= Seq("-Xss8m", "-Xmx4g"),
    Compile / run / mainClass := None
  )
