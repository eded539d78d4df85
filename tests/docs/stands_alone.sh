#!/bin/sh
# The repository stands alone: no tracked file names a folder of a developer's machine (a clone in
# /tmp, a worktree under /work) or a file outside the repository (the team's shared spec, design
# and style notes), because users have none of them. Report scripts write build folders as
# build/PRESET (scripts/lib/doc-paths.sh). Usage: stands_alone.sh SOURCE_DIR
set -u
cd "$1" || exit 2
# The patterns are split so that this file does not match itself.
machine='/tmp/[a-z0-9-]*clo''ne|/tmp/ldoem''-old|/w''ork/'
outside='\.\./sha''red|sha''red/spec|sha''red/DESIGN|sha''red/STYLE|(^|[^/a-z])(DES''IGN|STY''LE)\.md'
found=$(git grep -n -I -E "$machine|$outside" -- . ':!*.png' ':!*.svg' 2>/dev/null)
if [ -n "$found" ]; then
  echo "files name a path of a developer's machine or a file outside the repository:" >&2
  echo "$found" >&2
  exit 1
fi
echo "no machine paths and no references outside the repository"
