# shellcheck shell=bash
# Sourced by scripts/build-image.sh and scripts/check-fleet.sh: the podman settings under which
# containers run on machines like CI's (docs/scaling.md, "Podman on this kind of machine"):
#   - runtime runc: crun fails on a kernel with hybrid cgroups (v1 controllers, a v2 mount);
#   - cgroup_manager cgroupfs: no systemd is running to hand out cgroups;
#   - default_ulimits at or below the host's hard limits: podman's defaults ask for more
#     (nofile 1048576, nproc 4194304) and raising a hard limit is not permitted here;
#   - events_logger file: no journald.
# podman_setup writes /etc/containers/containers.conf when it is absent, or when it is the file
# this function wrote (marked) and its values changed; a foreign file is replaced only in CI
# (CI=true) as root, with a copy kept beside it, else left alone and named in a warning.
podman_conf=/etc/containers/containers.conf
podman_conf_marker="# written by ldoem scripts/lib/podman-setup.sh"

podman_conf_text() {
  local nofile nproc
  nofile=$(ulimit -Hn)
  nproc=$(ulimit -Hu)
  [[ $nofile == unlimited || $nofile -gt 16384 ]] && nofile=16384
  [[ $nproc == unlimited || $nproc -gt 4096 ]] && nproc=4096
  cat <<EOF
$podman_conf_marker (docs/scaling.md): runc, cgroupfs and limits
# below this host's hard limits (nofile $(ulimit -Hn), nproc $(ulimit -Hu)).
[containers]
default_ulimits = ["nofile=$nofile:$nofile", "nproc=$nproc:$nproc"]

[engine]
runtime = "runc"
cgroup_manager = "cgroupfs"
events_logger = "file"
EOF
}

podman_setup() {  # TOOL: the caller's name for messages
  local tool=$1 wanted
  wanted=$(podman_conf_text)
  if [[ -f $podman_conf ]] && [[ $(cat "$podman_conf") == "$wanted" ]]; then
    return 0
  fi
  if [[ -f $podman_conf ]] && ! head -n 1 "$podman_conf" | grep -qF "$podman_conf_marker"; then
    if [[ ${CI:-} != true || $(id -u) -ne 0 ]]; then
      echo "$tool: warning: $podman_conf exists and is not ours: left alone; podman may need" \
        'runtime = "runc", cgroup_manager = "cgroupfs" and lower default_ulimits (docs/scaling.md)' >&2
      return 0
    fi
    cp "$podman_conf" "$podman_conf.before-ldoem"
    echo "$tool: CI: replacing $podman_conf (the old one is $podman_conf.before-ldoem)" >&2
  fi
  if [[ $(id -u) -ne 0 ]]; then
    echo "$tool: warning: cannot write $podman_conf as $(id -un); podman keeps its defaults" >&2
    return 0
  fi
  mkdir -p "$(dirname "$podman_conf")"
  printf '%s\n' "$wanted" >"$podman_conf"
  echo "$tool: wrote $podman_conf (runc, cgroupfs, default_ulimits below the hard limits)" >&2
}
