#!/usr/bin/env bash
# Builds the ldoem OCI image (docs/scaling.md, "The fleet") from Debian's packages and the
# project's .deb, without pulling any base image:
#   1. the base: a Debian 12 root by mmdebstrap (variant essential), plus the runtime libraries
#      the .deb depends on (pinned to the versions apt's lists name) and socat (the
#      tilt stepper's LPT bridge between pods), without docs, man pages and locales;
#      cached by its recipe in ${LDOEM_CACHE:-~/.cache/ldoem}/image/;
#   2. the image: the base + the .deb + the user ldoem (10001) + deploy/image/ldoem-healthcheck,
#      every mtime clamped to SOURCE_DATE_EPOCH, imported with `podman import --change ...`
#      as localhost/ldoem:KEY (KEY: a hash of the base recipe, the .deb's files and the image
#      files); an image of that KEY already in podman's store is used as it is.
# Prints the image name as its last line on stdout.
set -euo pipefail

usage() {
  cat <<'EOF'
usage: scripts/build-image.sh [--build-dir DIR | --deb FILE] [--epoch SECONDS] [--rebuild-base]

Builds localhost/ldoem:KEY: a minimal Debian 12 root (mmdebstrap, variant essential) with the
runtime libraries of the project's .deb and the .deb itself, a non-root user (ldoem, 10001),
the scenes (/usr/share/ldoem/scenes), ldoem-emud as the entry point, a host-protocol health
check (ldoem-healthcheck: one GET_STATUS over TCP) and the flash folder /var/lib/ldoem as a
volume. Prints the image name last.

  --build-dir DIR    make the .deb with `cpack -G DEB` in DIR (default build/default; the
                     programs must be built there)
  --deb FILE         use this .deb instead
  --epoch SECONDS    SOURCE_DATE_EPOCH for the root's files and the image (default: the
                     environment's SOURCE_DATE_EPOCH, else 1686355200, Debian 12's release day)
  --rebuild-base     build the base root again even when it is cached

Environment: LDOEM_CACHE (default ~/.cache/ldoem): the base root and downloaded packages are
kept in LDOEM_CACHE/image/. Needs root (mmdebstrap, chroot, podman), mmdebstrap and podman;
writes /etc/containers/containers.conf if absent (scripts/lib/podman-setup.sh).
Exit status: 0 built (or found), 1 a step failed, 2 usage error.
EOF
}

cd "$(dirname "$0")/.."
tool=build-image
build_dir=build/default
deb=""
rebuild_base=false
epoch=${SOURCE_DATE_EPOCH:-}
while [[ $# -gt 0 ]]; do
  case $1 in
    --build-dir) build_dir=${2:?--build-dir needs a folder}; shift 2 ;;
    --deb) deb=${2:?--deb needs a file}; shift 2 ;;
    --epoch) epoch=${2:?--epoch needs seconds}; shift 2 ;;
    --rebuild-base) rebuild_base=true; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "$tool: unknown argument '$1' (try --help)" >&2; exit 2 ;;
  esac
done
# A fixed default (Debian 12's release day), not the last commit's time: a commit that leaves
# the image's files alone must find the cached image.
[[ -z $epoch ]] && epoch=1686355200
[[ $epoch =~ ^[0-9]+$ ]] || { echo "$tool: --epoch expects seconds, got '$epoch'" >&2; exit 2; }
export SOURCE_DATE_EPOCH=$epoch
[[ $(id -u) -eq 0 ]] || { echo "$tool: needs root (mmdebstrap, chroot, podman import)" >&2; exit 1; }
for program in mmdebstrap podman; do
  command -v "$program" >/dev/null || { echo "$tool: $program is missing (scripts/install-deps.sh)" >&2; exit 1; }
done
source scripts/lib/podman-setup.sh
podman_setup "$tool"

cache=${LDOEM_CACHE:-$HOME/.cache/ldoem}/image
mkdir -p "$cache/debs"
work=$(mktemp -d "${TMPDIR:-/tmp}/ldoem-image.XXXXXX")
trap 'rm -rf "$work"' EXIT
started=$SECONDS

if [[ -z $deb ]]; then
  [[ -x $build_dir/emulator/daemon/ldoem-emud ]] ||
    { echo "$tool: $build_dir has no ldoem-emud: build the programs first (docs/service.md)" >&2; exit 1; }
  (cd "$build_dir" && cpack -G DEB -B "$work/deb" >/dev/null)
  deb=$(ls "$work"/deb/*.deb)
fi
[[ -f $deb ]] || { echo "$tool: no .deb at $deb" >&2; exit 1; }

# The base's packages: the .deb's Depends, less those the emulator and the hub never use in a
# container (left_out: systemd, as a container has no init and the units are of no use in it;
# python3 and numpy, for the Python package, about 60 MB), plus socat; each pinned to the
# version apt's lists here name as candidate (the mirror's newest), so the recipe, and the
# cache key, say exactly what goes in.
left_out=(systemd python3 python3-numpy)
packages=()
while read -r name; do
  [[ -z $name || " ${left_out[*]} " == *" $name "* ]] && continue
  version=$(apt-cache policy "$name" | sed -n 's/^ *Candidate: //p')
  [[ -n $version && $version != "(none)" ]] || { echo "$tool: no version of $name found" >&2; exit 1; }
  packages+=("$name=$version")
done < <({ dpkg-deb -f "$deb" Depends | tr ',' '\n' | sed 's/(.*//; s/|.*//; s/ //g'; echo socat; } | sort -u)

# The mirror: this machine's Debian sources (deb822 or one-line files), as apt uses them.
mirrors=()
for file in /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources; do
  [[ -f $file ]] && grep -q 'debian' "$file" && mirrors+=("$file")
done
[[ ${#mirrors[@]} -gt 0 ]] || { echo "$tool: no Debian apt sources in /etc/apt" >&2; exit 1; }

# Paths no container needs: docs, manuals, translations, and the .deb's development files.
# Quoted: the globs are the root's, expanded inside it (below), never this machine's.
excludes=('/usr/share/doc/*' '/usr/share/man/*' '/usr/share/info/*' '/usr/share/locale/*' '/usr/share/lintian/*'
          '/usr/include/*' '/usr/lib/libldoem*.a' '/usr/lib/cmake/*' '/usr/lib/pkgconfig/*'
          '/usr/lib/x86_64-linux-gnu/libldoem*.a' '/usr/lib/x86_64-linux-gnu/cmake/ldoem'
          '/usr/lib/x86_64-linux-gnu/pkgconfig/ldoem.pc' '/usr/lib/x86_64-linux-gnu/wireshark'
          '/usr/lib/python3' '/usr/share/bash-completion'  # the Python package: no interpreter here
          '/usr/lib/x86_64-linux-gnu/gconv/*'  # iconv's converters: no program here uses iconv
          # perl-base is Essential, so dpkg installs it, but nothing in the image runs perl (it
          # has no apt, and nothing installs packages into it after this script): 9 MB.
          '/usr/bin/perl*' '/usr/lib/x86_64-linux-gnu/perl-base')
base_recipe=$(printf '%s\n' "mode=unshare variant=essential merged-usr" "${packages[@]}" "${excludes[@]}" "epoch=$epoch" \
                "$(cat "${mirrors[@]}")" | sha256sum | cut -c1-16)
base=$cache/base-$base_recipe.tar

if [[ ! -s $base || $rebuild_base == true ]]; then
  echo "$tool: base root (mmdebstrap, ${#packages[@]} packages pinned) -> $base" >&2
  # The excluded paths are removed after the install: dpkg's path-exclude, set for the whole
  # run, made dpkg fail on the libraries' docs in the second stage (mmdebstrap 1.3.5).
  dpkg_options=(--dpkgopt=force-unsafe-io)
  include=$(IFS=,; echo "${packages[*]}")
  # Packages downloaded once are kept in the cache and handed to the next build.
  # The merged-usr hook makes /bin, /lib... links itself: otherwise the usrmerge package comes
  # in, and with it the whole of perl (about 55 MB).
  # --mode=unshare: the chroot's /proc, /sys, /dev/pts and /dev/shm are mounted in a namespace
  # of its own, which ends with mmdebstrap. In root mode they are mounted on this machine, the
  # host's /dev/shm bound in, and one run here left them mounted ("target is busy") and failed.
  if ! mmdebstrap --mode=unshare --variant=essential "${dpkg_options[@]}" --include="$include" \
      --hook-dir=/usr/share/mmdebstrap/hooks/merged-usr \
      --setup-hook='mkdir -p "$1"/var/cache/apt/archives' \
      --setup-hook="sync-in $cache/debs /var/cache/apt/archives" \
      --customize-hook="sync-out /var/cache/apt/archives $cache/debs" \
      --customize-hook='rm -f "$1"/var/cache/apt/archives/*.deb "$1"/var/log/*.log "$1"/var/cache/ldconfig/aux-cache' \
      --customize-hook="cd \"\$1\" && rm -rf $(printf '.%s ' "${excludes[@]}")" \
      --skip=download/empty bookworm "$work/base.tar" "${mirrors[@]}" >"$work/mmdebstrap.log" 2>&1; then
    cp "$work/mmdebstrap.log" "$cache/mmdebstrap-failed.log"
    grep -v "^\(Get:\|Preparing\|Unpacking\|Selecting\|Setting up\|(Reading\)" "$work/mmdebstrap.log" | tail -n 30 >&2
    echo "$tool: mmdebstrap failed (the last lines above; the whole log: $cache/mmdebstrap-failed.log)" >&2
    exit 1
  fi
  rm -f "$cache"/base-*.tar
  mv "$work/base.tar" "$base"
fi

# The image's key: the base, the .deb's files that stay in the image (not the .deb's own bytes,
# which carry build times, nor its docs) and the files this script puts in.
mkdir "$work/x" && dpkg-deb -x "$deb" "$work/x"
(cd "$work/x" && for path in "${excludes[@]}"; do rm -rf .$path; done)  # unquoted: the tree's globs
deb_files=$(cd "$work/x" && find . -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum | cut -c1-16)
key=$(cat <(echo "$base_recipe $deb_files $epoch") deploy/image/ldoem-healthcheck "$0" | sha256sum | cut -c1-16)
image=localhost/ldoem:$key
if podman image exists "$image"; then
  echo "$tool: $image is cached ($((SECONDS - started)) s)" >&2
  echo "$image"
  exit 0
fi

echo "$tool: assembling $image" >&2
root=$work/root
mkdir "$root"
tar -C "$root" -xf "$base"
cp "$deb" "$root/tmp/ldoem.deb"
# The dependencies left out on purpose (above); no maintainer script of the .deb needs them.
chroot "$root" dpkg --ignore-depends="$(IFS=,; echo "${left_out[*]}")" -i /tmp/ldoem.deb >"$work/dpkg.log" 2>&1 ||
  { cat "$work/dpkg.log" >&2; echo "$tool: dpkg -i the .deb failed" >&2; exit 1; }
rm -f "$root/tmp/ldoem.deb" "$root"/var/log/*.log
(cd "$root" && for path in "${excludes[@]}"; do rm -rf .$path; done)  # unquoted: the root's globs
install -m 0755 deploy/image/ldoem-healthcheck "$root/usr/local/bin/ldoem-healthcheck"
# The user: fixed ids, so a volume's owner means the same in every image and on every node.
echo 'ldoem:x:10001:10001:ldoem emulator:/var/lib/ldoem:/usr/sbin/nologin' >>"$root/etc/passwd"
echo 'ldoem:x:10001:' >>"$root/etc/group"
echo 'ldoem:!:19000::::::' >>"$root/etc/shadow"
install -d -m 0750 -o 10001 -g 10001 "$root/var/lib/ldoem"   # the flash files (a volume)
install -d -m 0755 -o 10001 -g 10001 "$root/run/ldoem"       # the ptys' links (LPT, serial)
dpkg-query --admindir="$root/var/lib/dpkg" -W -f='${Package}=${Version}\n' | sort >"$root/usr/share/ldoem/image-packages.txt"
# Every file's time is the epoch (the .deb's files carry their build time).
tar -C "$root" --sort=name --numeric-owner --mtime="@$epoch" \
  --pax-option=exthdr.name=%d/PaxHeaders/%f,delete=atime,delete=ctime -cf "$work/image.tar" .

podman import --quiet \
  --change 'ENTRYPOINT ["/usr/bin/ldoem-emud"]' \
  --change 'CMD ["--scene", "/usr/share/ldoem/scenes/corridor.yaml", "--no-can", "--tcp", "tcp:0.0.0.0:49152", "--flash-dir", "/var/lib/ldoem"]' \
  --change 'USER 10001:10001' \
  --change 'WORKDIR /var/lib/ldoem' \
  --change 'VOLUME /var/lib/ldoem' \
  --change 'EXPOSE 49152/tcp' \
  --change 'ENV PATH=/usr/local/bin:/usr/bin:/bin' \
  --change 'ENV STATE_DIRECTORY=/var/lib/ldoem' \
  --change 'STOPSIGNAL SIGTERM' \
  --change 'LABEL org.opencontainers.image.title=ldoem' \
  --change "LABEL org.opencontainers.image.created=$(date -u -d "@$epoch" +%Y-%m-%dT%H:%M:%SZ)" \
  --change 'LABEL io.ldoem.healthcheck="/usr/local/bin/ldoem-healthcheck 127.0.0.1:49152"' \
  "$work/image.tar" "$image" >/dev/null
# Older images of this script are not kept: one cached image at a time.
podman images --format '{{.Repository}}:{{.Tag}}' | grep '^localhost/ldoem:' | grep -vxF "$image" |
  xargs -r podman rmi --force >/dev/null 2>&1 || true
size=$(podman image inspect --format '{{.Size}}' "$image")
echo "$tool: $image: $((size / 1000000)) MB, root tar sha256 $(sha256sum "$work/image.tar" | cut -c1-16)," \
  "$((SECONDS - started)) s" >&2
echo "$image"
