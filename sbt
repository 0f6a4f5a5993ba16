#!/usr/bin/env bash
# sbt wrapper: fetches the sbt launcher from Maven Central (via Maven) if it is
# missing, and pins every resolver to Maven Central (project/repositories), so
# a fresh Debian machine needs nothing but a JDK and Maven.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
version="$(sed -n 's/^sbt.version *= *//p' "$here/project/build.properties")"
jar="${HOME}/.m2/repository/org/scala-sbt/sbt-launch/${version}/sbt-launch-${version}.jar"
if [ ! -f "$jar" ]; then
  echo "sbt: fetching org.scala-sbt:sbt-launch:${version} from Maven Central" >&2
  mvn -q dependency:get -Dartifact="org.scala-sbt:sbt-launch:${version}" -Dtransitive=false >&2
fi
# -Xss8m: Chisel elaboration and firtool's Scala front end recurse deeply.
exec java -Xss8m -Xmx4g ${SBT_JAVA_OPTS:-} \
  -Dsbt.override.build.repos=true \
  -Dsbt.repository.config="$here/project/repositories" \
  -Dsbt.supershell=false -Dsbt.server.forcestart=false \
  -jar "$jar" "$@"
