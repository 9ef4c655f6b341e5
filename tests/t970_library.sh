#!/bin/sh
# t970_library.sh: libperistatic as a program of one's own uses it. The
# example examples/plate_from_arrays.c is compiled with the flags
# pkg-config gives for the library in this build tree
# (peristatic-uninstalled.pc) and run; it builds a plate's particles as
# arrays and runs the case from YAML text. The same plate written as a
# point cloud and run by `peristatic run` must give the same numbers to the
# digits both print (the same arithmetic on the same particles: any
# difference means the interface set something up differently). The
# shared library must export only the public interface (peristatic_*).
srcdir=${srcdir:-.}
P=./peristatic
T=t970_tmp
. "$srcdir/tests/cli_lib.sh"
rm -rf "$T"
mkdir -p "$T"
CC=${CC:-cc}
PC="env PKG_CONFIG_PATH=. pkg-config"

if [ "$($PC --modversion peristatic-uninstalled)" = "$($P --version | cut -d' ' -f2)" ]; then
  ok "pkg-config: peristatic-uninstalled has the program's version"
else
  ko "pkg-config --modversion peristatic-uninstalled"
fi
# the public header alone, in strict C99 and C11
for std in c99 c11; do
  printf '#include <peristatic.h>\nint main(void) { return peristatic_version() == 0; }\n' \
    > "$T/hdr.c"
  if $CC -std=$std -pedantic -Wall -Wextra -Werror -c -o "$T/hdr.o" "$T/hdr.c" \
       $($PC --cflags peristatic-uninstalled) 2> "$T/hdr.err"; then
    ok "peristatic.h compiles alone (-std=$std -pedantic -Werror)"
  else
    ko "peristatic.h alone (-std=$std): $(cat "$T/hdr.err")"
  fi
done
if $CC -std=c11 -Wall -Wextra -Werror -o "$T/example" "$srcdir/examples/plate_from_arrays.c" \
     $($PC --cflags --libs peristatic-uninstalled) 2> "$T/cc.err"; then
  ok "the example builds with pkg-config's flags"
else
  ko "the example does not build: $(cat "$T/cc.err")"
fi
if LD_LIBRARY_PATH=.libs "$T/example" "$T/cloud.txt" > "$T/example.out" 2> "$T/example.err"; then
  ok "the example runs (exit 0)"
else
  ko "the example failed: $(cat "$T/example.err")"
fi
grep -q "^particles 192$" "$T/example.out" && ok "the example reads back its 192 particles" ||
  ko "particles: $(grep particles "$T/example.out")"

# the same plate from a case file through the program
sed -e 's/^    "//' -e 's/\\n"$//' -e 's/\\n";$//' "$srcdir/examples/plate_from_arrays.c" |
  sed -n '/^name: plate-from-arrays/,/^path:/p' |
  sed 's|^geometry: {type: cloud, dim: 2}|geometry: {type: cloud, dim: 2, file: cloud.txt}|' \
  > "$T/plate.yaml"
if $P run -q -t 1 -o "$T/run" "$T/plate.yaml" 2> "$T/run.err"; then
  ok "peristatic run solves the same plate from a cloud file"
else
  ko "peristatic run on the cloud file: $(cat "$T/run.err")"
fi
same() { # NAME VALUE_FROM_EXAMPLE VALUE_FROM_RUN
  if [ -n "$2" ] && [ "$2" = "$3" ]; then ok "$1: $2 through the library and the program"
  else ko "$1: library $2, program $3"; fi
}
ex() { awk -v k="$1" '$1 == k { print $2 }' "$T/example.out"; }
sm() { awk -v k="$1:" '$1 == k { print $2 }' "$T/run/summary.txt"; }
same arms "$(ex arms)" "$(sm arms)"
same newton_iterations "$(ex newton_iterations)" "$(sm newton_iterations)"
same "peak boundary stress" "$(ex peak_boundary_stress_Pa)" "$(sm sigma_failure_Pa)"
for a in 191 180; do
  same "particle $a displacement" \
    "$(awk -v a=$a '$1 == "particle" && $2 == a { print $4, $6 }' "$T/example.out")" \
    "$(awk -F, -v a=$a '$1 == a { print $4, $5 }' "$T/run/particles.csv")"
done

# installed into a temporary root (the library, its header and its
# pkg-config file; DESTDIR), the example builds with the flags the
# installed peristatic.pc gives (PKG_CONFIG_SYSROOT_DIR maps its paths into
# the root) and runs against the installed library alone
root="$(pwd)/$T/root"
if make install-libLTLIBRARIES install-includeHEADERS install-pkgconfigDATA \
     DESTDIR="$root" > "$T/install.log" 2>&1; then
  pcdir=$(dirname "$(find "$root" -name peristatic.pc | head -1)")
  libdir=$(dirname "$(find "$root" -name 'libperistatic.so' | head -1)")
  flags=$(PKG_CONFIG_PATH="$pcdir" PKG_CONFIG_SYSROOT_DIR="$root" \
          pkg-config --cflags --libs peristatic 2> "$T/pc.err")
  if [ -f "$pcdir/peristatic.pc" ] && printf '%s' "$flags" | grep -q -- "-L$root" &&
     $CC -std=c11 -Wall -Werror -o "$T/example_installed" \
       "$srcdir/examples/plate_from_arrays.c" $flags 2> "$T/cc2.err" &&
     LD_LIBRARY_PATH="$libdir" "$T/example_installed" > "$T/installed.out" &&
     cmp -s "$T/installed.out" "$T/example.out"; then
    ok "installed (DESTDIR): the example builds with pkg-config --cflags --libs peristatic and prints the same"
  else
    ko "installed library: flags '$flags' $(cat "$T/pc.err" "$T/cc2.err" 2>/dev/null)"
  fi
else
  ko "make install into a temporary root: $(tail -5 "$T/install.log")"
fi

# the shared library's interface: peristatic_* only
if [ -f .libs/libperistatic.so ]; then
  other=$(nm -D --defined-only .libs/libperistatic.so | awk '$2 ~ /[TDBR]/ { print $3 }' |
          grep -v '^peristatic_' | grep -v '^_' | head -5)
  [ -z "$other" ] && ok "libperistatic.so exports only peristatic_* symbols" ||
    ko "libperistatic.so exports internal symbols: $other"
else
  ko "no shared library .libs/libperistatic.so (configure --disable-shared?)"
fi
summary
