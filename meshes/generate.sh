#!/usr/bin/env bash
# aries meshes: generate (once) and print the path of a cached mesh.
#
#   meshes/generate.sh NAME [SIZE]   print the path of meshes/cache/NAME_SIZE.msh, building it first
#                                    if it is missing or was built by other generator sources.
#                                    SIZE: test | default (the default) | paper
#   meshes/generate.sh all [SIZE]    build every mesh of that size; prints one path per line
#   meshes/generate.sh h5 NAME [SIZE]
#                                    print the path of meshes/cache/NAME_SIZE.h5, the .msh converted (once)
#                                    by aries -mesh_convert to aries' HDF5 mesh, which every rank reads in
#                                    parallel; needs the aries binary ($ARIES_BIN, default build/aries)
#   meshes/generate.sh list          names, sizes, kinds (tet/tri), parameters, expected cell counts
#
# stdout carries only the path(s); the build log goes to stderr. Sizes are fixed presets (anything
# else is refused), and each build is bounded: 8 GiB of address space and 15 minutes.
# Next to NAME_SIZE.msh the cache holds NAME_SIZE.json (counts, quality, provenance), for the
# octopus NAME_SIZE.fibers (per-cell fiber directions), and NAME_SIZE.stamp (generator hash).
# Files appear atomically (built in a temporary directory, renamed into place, the .msh last);
# concurrent calls for the same mesh wait for each other (flock). See meshes/README.md.
set -euo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
PY=/usr/bin/python3                 # Debian's python (numpy); not whatever python3 is on PATH
export PYTHONDONTWRITEBYTECODE=1
BUILD="$HERE/tools/build.py"
CATALOG="$HERE/tools/catalog.py"  # no numpy: asked on every call, cached mesh or not
CACHE="${ARIES_MESH_CACHE:-$HERE/cache}"
MEM_LIMIT_KB=$((8 * 1024 * 1024))
TIME_LIMIT=900

die() { echo "generate.sh: $*" >&2; exit 2; }

usage() { sed -n '2,19p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }

[ -x "$PY" ] || die "$PY not found (apt-get install python3-numpy)"
command -v gmsh >/dev/null || die "gmsh not found (apt-get install gmsh)"

# gmsh's version, kept in the cache next to the identity of the gmsh on PATH (path, inode, size, mtime: an upgrade
# replaces the file): `gmsh -version` loads all of libgmsh (0.2 s), and every call asks for the stamp.
gmsh_version() {
  local bin id v file="$CACHE/.gmsh-version"
  bin="$(command -v gmsh)"
  id="$(stat -L -c '%n %i %s %Y' "$bin")"
  if [ -f "$file" ] && [ "$(head -n 1 "$file")" = "$id" ]; then
    tail -n +2 "$file"
    return 0
  fi
  v="$(gmsh -version 2>&1 || true)"
  mkdir -p "$CACHE"
  printf '%s\n%s\n' "$id" "$v" > "$file.$$" && mv -f "$file.$$" "$file"
  printf '%s\n' "$v"
}

# Hash of everything that determines the mesh bytes: generator sources and the gmsh version.
stamp() {
  {
    cat "$HERE/generate.sh" "$HERE"/tools/*.py "$HERE"/geo/*.geo
    gmsh_version
  } | sha256sum | cut -c1-16
}

generate() {
  local name="$1" size="$2" canon out key st tmp
  canon="$("$PY" "$CATALOG" resolve "$name" "$size")" || exit 2
  key="${name}_${canon}"
  out="$CACHE/$key.msh"
  st="$(stamp)"
  if [ -f "$out" ] && [ "$(cat "$CACHE/$key.stamp" 2>/dev/null)" = "$st" ]; then
    echo "$out"
    return 0
  fi
  mkdir -p "$CACHE"
  exec 9>"$CACHE/.$key.lock"
  flock 9
  # someone else may have finished it while we waited
  if [ -f "$out" ] && [ "$(cat "$CACHE/$key.stamp" 2>/dev/null)" = "$st" ]; then
    exec 9>&-
    echo "$out"
    return 0
  fi
  rm -rf "$CACHE/.tmp.$key".*             # leftovers of an interrupted build (we hold the lock)
  tmp="$(mktemp -d "$CACHE/.tmp.$key.XXXXXX")"
  trap "rm -rf '$tmp'" EXIT
  echo "generate.sh: building $key (log below)" >&2
  # timeout runs the build in its own process group and forwards INT/TERM to all of it (gmsh too)
  (ulimit -v "$MEM_LIMIT_KB"; exec timeout "$TIME_LIMIT" "$PY" "$BUILD" build "$name" "$canon" "$tmp") >&2 &
  local bpid=$!
  trap "kill -TERM $bpid 2>/dev/null; wait $bpid; rm -rf '$tmp'; exit 130" INT TERM
  if ! wait "$bpid"; then
    die "building $key failed (limits: ${MEM_LIMIT_KB} KiB address space, ${TIME_LIMIT} s)"
  fi
  trap - INT TERM
  rm -f "$CACHE/$key.stamp"
  local f
  for f in "$tmp/$key".*; do
    [ "$f" = "$tmp/$key.msh" ] || mv -f "$f" "$CACHE/"
  done
  mv -f "$tmp/$key.msh" "$out"            # the .msh last: its presence means the set is complete
  echo "$st" > "$tmp/stamp" && mv -f "$tmp/stamp" "$CACHE/$key.stamp"
  rm -rf "$tmp"
  trap - EXIT
  exec 9>&-
  echo "$out"
}

# The HDF5 copy of a cached mesh, converted by aries itself (so the file matches the reader); rebuilt when the .msh
# is newer or the file's format (root attribute aries_mesh_format) is not the one aries reads. Triangle meshes are converted in 3D (the cloth and UV scenes' reading; a planar 2D run, Cook's membrane,
# reads the .msh).
H5_FORMAT=aries-mesh-2  # mesh/mesh_hdf5.cpp kMeshFormat
h5_format() {
  "$PY" -c 'import h5py,sys; v=h5py.File(sys.argv[1],"r").attrs.get("aries_mesh_format",b""); print(v.decode() if isinstance(v,bytes) else v)' "$1" 2>/dev/null || true
}

convert_h5() {
  local msh="$1" h5 aries json args=()
  h5="${msh%.msh}.h5"
  json="${msh%.msh}.json"
  aries="${ARIES_BIN:-$HERE/../build/aries}"
  if [ -f "$h5" ] && [ "$h5" -nt "$msh" ] && [ "$(h5_format "$h5")" = "$H5_FORMAT" ]; then
    echo "$h5"
    return 0
  fi
  [ -x "$aries" ] || die "no aries binary at $aries to convert $msh (build it, or set ARIES_BIN)"
  if [ -f "$json" ] && "$PY" -c 'import json,sys; sys.exit(0 if "triangles" in json.load(open(sys.argv[1])) else 1)' "$json"; then
    args=(-dm_plex_gmsh_spacedim 3)
  fi
  exec 9>"$CACHE/.$(basename "$h5").lock"
  flock 9
  "$aries" -dm_plex_filename "$msh" "${args[@]}" -mesh_convert "$h5.part.h5" >&2 || die "converting $msh failed"
  mv -f "$h5.part.h5" "$h5"
  exec 9>&-
  echo "$h5"
}

case "${1:-}" in
  ""|-h|--help|help) usage ;;
  h5)
    [ $# -ge 2 ] && [ $# -le 3 ] || usage
    convert_h5 "$(generate "$2" "${3:-default}")" ;;
  list) exec "$PY" "$CATALOG" list ;;
  all)
    [ $# -le 2 ] || usage
    # one generate.sh per mesh, as many at once as there are cores (each gmsh runs on one thread; the per-mesh locks
    # keep concurrent builds of one mesh apart); the paths are printed as each finishes
    "$PY" "$CATALOG" names | xargs -P "$(nproc)" -I{} "$HERE/generate.sh" {} "${2:-default}" ;;
  *)
    [ $# -le 2 ] || usage
    generate "$1" "${2:-default}" ;;
esac
