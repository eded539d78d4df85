#!/usr/bin/env python3
"""Writes the fleet's manifests (docs/scaling.md, "The fleet") from one description, two ways:

  kubernetes  a StatefulSet of N emulated scanners (the scene from a ConfigMap, the flash on a
              volume per scanner), a Service per scanner, and the hub as a Deployment with the
              scanners' addresses: deploy/kubernetes/fleet.yaml is this output for N = 3;
  podman      the same containers as plain Pods for `podman kube play`, which has no StatefulSet
              and no Service: one Pod and one PersistentVolumeClaim per scanner, on the host's
              network (hostNetwork: true), each on its own loopback ports.

Both share the containers below: their commands, probes, resources and security settings.
"""
import argparse
import json
import pathlib
import sys

SCANNER_PORT = 49152  # the host protocol on TCP (spec 4.1)
LPT_PORT = 49153      # the tilt stepper's drive register, bridged from the hub (socat)
HUB_PORT = 49200
USER = 10001          # the image's user ldoem (scripts/build-image.sh)

# Sized from docs/scaling.md: a corridor scanner's loop uses 0.0024 CPU s per simulated second
# and its daemon about 15 MiB resident (76 MiB for scenes/large.yaml); the limits leave room for
# the scene's loading and the BVH build at start, and for a larger scene.
SCANNER_RESOURCES = {"requests": {"cpu": "20m", "memory": "32Mi"},
                     "limits": {"cpu": "500m", "memory": "256Mi"}}
HUB_RESOURCES = {"requests": {"cpu": "20m", "memory": "16Mi"},
                 "limits": {"cpu": "500m", "memory": "128Mi"}}
SECURITY = {"runAsNonRoot": True, "runAsUser": USER, "runAsGroup": USER,
            "allowPrivilegeEscalation": False, "readOnlyRootFilesystem": True,
            "capabilities": {"drop": ["ALL"]}}


def dump(value, indent=0):
    """YAML for the plain values used here (dicts, lists, strings, numbers, booleans)."""
    pad = "  " * indent
    lines = []
    if isinstance(value, dict):
        for key, item in value.items():
            if isinstance(item, (dict, list)) and item:
                lines.append(f"{pad}{key}:")
                lines.extend(dump(item, indent + 1))
            elif isinstance(item, str) and "\n" in item:
                lines.append(f"{pad}{key}: |")
                lines.extend(f"{pad}  {line}" if line else "" for line in item.rstrip("\n").split("\n"))
            else:
                lines.append(f"{pad}{key}: {scalar(item)}")
    else:
        for item in value:
            if not isinstance(item, (dict, list)):
                lines.append(f"{pad}- {scalar(item)}")
                continue
            sub = dump(item, indent + 1)
            lines.append(f"{pad}- {sub[0].lstrip()}")
            lines.extend(sub[1:])
    return lines


def scalar(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, float)):
        return str(value)
    return json.dumps(value)  # a JSON string, {} or [] is YAML too


def without_ports(container):
    # podman kube play refuses containerPort with hostNetwork ("PortMappings can only be used
    # with Bridge or slirp4netns networking"); the ports are the command's anyway.
    return {key: value for key, value in container.items() if key != "ports"}


def scanner_container(image, bind, port, lpt_port):
    # The LPT bridge: the hub writes the drive register to a pty of its own; socat carries each
    # byte over TCP to this pod and writes it to the daemon's pty (/run/ldoem/lpt), in order.
    # ldoem-emud is exec'd, so it gets SIGTERM and saves the flash (exit 143).
    command = (f"socat TCP-LISTEN:{lpt_port},bind={bind},reuseaddr,fork,nodelay FILE:/run/ldoem/lpt,raw,echo=0 & "
               f"exec /usr/bin/ldoem-emud --scene /etc/ldoem/scene/scene.yaml --flash-dir /var/lib/ldoem "
               f"--no-can --tcp tcp:{bind}:{port} --lpt lpt:pty:/run/ldoem/lpt")
    probe = ["/usr/local/bin/ldoem-healthcheck", f"127.0.0.1:{port}"]
    return {
        "name": "ldoem-emud",
        "image": image,
        "imagePullPolicy": "IfNotPresent",
        "command": ["/bin/sh", "-c", command],
        "ports": [{"name": "host-protocol", "containerPort": port, "protocol": "TCP"},
                  {"name": "lpt", "containerPort": lpt_port, "protocol": "TCP"}],
        # One GET_STATUS answered by the daemon's loop (deploy/image/ldoem-healthcheck).
        "readinessProbe": {"exec": {"command": probe}, "initialDelaySeconds": 1, "periodSeconds": 5,
                           "timeoutSeconds": 6},
        "livenessProbe": {"exec": {"command": probe}, "initialDelaySeconds": 5, "periodSeconds": 10,
                          "timeoutSeconds": 6, "failureThreshold": 3},
        "resources": SCANNER_RESOURCES,
        "securityContext": SECURITY,
        "volumeMounts": [{"name": "scene", "mountPath": "/etc/ldoem/scene", "readOnly": True},
                         {"name": "flash", "mountPath": "/var/lib/ldoem"},
                         {"name": "run", "mountPath": "/run/ldoem"}],
    }


def hub_container(image, listen, devices):
    # One bridge per scanner, started again whenever its connection ends (the scanner restarted):
    # the pty link /run/ldoem/lpt/NAME is what the hub configuration names as the device's LPT.
    bridges = " ".join(
        f"(while :; do socat PTY,link=/run/ldoem/lpt/{name},raw,echo=0 TCP:{host}:{lpt},nodelay; sleep 1; done) &"
        for name, host, _, lpt in devices)
    command = (f"mkdir -p /run/ldoem/lpt && {bridges} "
               f"exec /usr/bin/ldoem-hub --config /etc/ldoem/hub/hub.yaml --listen {listen}")
    port = int(listen.rsplit(":", 1)[1])
    # The hub's greeting (docs/hub.md) comes from its epoll loop: a hung loop fails the probe.
    probe = ["/usr/local/bin/ldoem-healthcheck", "--hub", f"127.0.0.1:{port}"]
    return {
        "name": "ldoem-hub",
        "image": image,
        "imagePullPolicy": "IfNotPresent",
        "command": ["/bin/sh", "-c", command],
        "ports": [{"name": "hub", "containerPort": port, "protocol": "TCP"}],
        "readinessProbe": {"exec": {"command": probe}, "periodSeconds": 5, "timeoutSeconds": 4},
        "livenessProbe": {"exec": {"command": probe}, "initialDelaySeconds": 5, "periodSeconds": 10,
                          "timeoutSeconds": 4, "failureThreshold": 3},
        "resources": HUB_RESOURCES,
        "securityContext": SECURITY,
        "volumeMounts": [{"name": "hub-config", "mountPath": "/etc/ldoem/hub", "readOnly": True},
                         {"name": "run", "mountPath": "/run/ldoem"}],
    }


def hub_yaml(devices):
    lines = ["# ldoem-hub's devices (docs/hub.md): the scanners' host protocol and their tilt steppers."]
    lines.append("devices:")
    for name, host, port, _ in devices:
        lines += [f"  - name: {name}", f"    scanner: tcp:{host}:{port}", f"    lpt: lpt:pty:/run/ldoem/lpt/{name}"]
    return "\n".join(lines) + "\n"


def config_map(name, labels, key, text):
    return {"apiVersion": "v1", "kind": "ConfigMap", "metadata": {"name": name, "labels": labels},
            "data": {key: text}}


def kubernetes(args, scene):
    labels = {"app.kubernetes.io/part-of": "ldoem-fleet"}
    scanner_labels = {**labels, "app.kubernetes.io/name": "ldoem-scanner"}
    hub_labels = {**labels, "app.kubernetes.io/name": "ldoem-hub"}
    devices = [(f"scanner-{k}", f"ldoem-scanner-{k}", SCANNER_PORT, LPT_PORT) for k in range(args.scanners)]
    docs = [config_map("ldoem-scene", labels, "scene.yaml", scene),
            config_map("ldoem-hub", labels, "hub.yaml", hub_yaml(devices))]
    docs.append({"apiVersion": "v1", "kind": "Service",
                 "metadata": {"name": "ldoem-scanner", "labels": scanner_labels},
                 "spec": {"clusterIP": "None", "selector": scanner_labels,
                          "ports": [{"name": "host-protocol", "port": SCANNER_PORT}]}})
    container = scanner_container(args.image, "0.0.0.0", SCANNER_PORT, LPT_PORT)
    docs.append({"apiVersion": "apps/v1", "kind": "StatefulSet",
                 "metadata": {"name": "ldoem-scanner", "labels": scanner_labels},
                 "spec": {"serviceName": "ldoem-scanner", "replicas": args.scanners,
                          "podManagementPolicy": "Parallel",
                          "selector": {"matchLabels": scanner_labels},
                          "template": {"metadata": {"labels": scanner_labels},
                                       "spec": {"securityContext": {"fsGroup": USER},
                                                "terminationGracePeriodSeconds": 15,
                                                "containers": [container],
                                                "volumes": [{"name": "scene", "configMap": {"name": "ldoem-scene"}},
                                                            {"name": "run", "emptyDir": {"medium": "Memory", "sizeLimit": "1Mi"}}]}},
                          "volumeClaimTemplates": [{"metadata": {"name": "flash"},
                                                    "spec": {"accessModes": ["ReadWriteOnce"],
                                                             "resources": {"requests": {"storage": "16Mi"}}}}]}})
    for k in range(args.scanners):
        docs.append({"apiVersion": "v1", "kind": "Service",
                     "metadata": {"name": f"ldoem-scanner-{k}", "labels": scanner_labels},
                     "spec": {"selector": {"statefulset.kubernetes.io/pod-name": f"ldoem-scanner-{k}"},
                              "ports": [{"name": "host-protocol", "port": SCANNER_PORT},
                                        {"name": "lpt", "port": LPT_PORT}]}})
    docs.append({"apiVersion": "apps/v1", "kind": "Deployment",
                 "metadata": {"name": "ldoem-hub", "labels": hub_labels},
                 "spec": {"replicas": 1, "selector": {"matchLabels": hub_labels},
                          "template": {"metadata": {"labels": hub_labels},
                                       "spec": {"containers": [hub_container(args.image, f"0.0.0.0:{HUB_PORT}", devices)],
                                                "volumes": [{"name": "hub-config", "configMap": {"name": "ldoem-hub"}},
                                                            {"name": "run", "emptyDir": {"medium": "Memory", "sizeLimit": "1Mi"}}]}}}})
    docs.append({"apiVersion": "v1", "kind": "Service",
                 "metadata": {"name": "ldoem-hub", "labels": hub_labels},
                 "spec": {"selector": hub_labels, "ports": [{"name": "hub", "port": HUB_PORT}]}})
    header = ("# Generated by deploy/kubernetes/render.py kubernetes --scanners %d: do not edit; change\n"
              "# render.py and run it again (scripts/check-fleet.sh fails when this file is stale).\n"
              "# The image: scripts/build-image.sh, tagged and pushed as `%s` (docs/scaling.md).\n"
              % (args.scanners, args.image))
    return header, docs


def podman(args, scene):
    p = args.prefix
    labels = {"app.kubernetes.io/part-of": p}
    ports = [(args.port_base + 2 * k, args.port_base + 2 * k + 1) for k in range(args.scanners)]
    devices = [(f"scanner-{k}", "127.0.0.1", port, lpt) for k, (port, lpt) in enumerate(ports)]
    docs = [config_map(f"{p}-scene", labels, "scene.yaml", scene),
            config_map(f"{p}-hub", labels, "hub.yaml", hub_yaml(devices))]
    # /run/ldoem (the ptys' links) is a named volume per pod: podman 4.3 makes an emptyDir a
    # named volume called as the pod's volume, so two pods naming `run` would share one.
    for k, (port, lpt) in enumerate(ports):
        docs.append({"apiVersion": "v1", "kind": "PersistentVolumeClaim",
                     "metadata": {"name": f"{p}-flash-scanner-{k}", "labels": labels},
                     "spec": {"accessModes": ["ReadWriteOnce"], "resources": {"requests": {"storage": "16Mi"}}}})
        docs.append({"apiVersion": "v1", "kind": "Pod",
                     "metadata": {"name": f"{p}-scanner-{k}", "labels": labels},
                     "spec": {"hostNetwork": True, "restartPolicy": "Never",
                              "containers": [without_ports(scanner_container(args.image, "127.0.0.1", port, lpt))],
                              "volumes": [{"name": "scene", "configMap": {"name": f"{p}-scene"}},
                                          {"name": "flash", "persistentVolumeClaim": {"claimName": f"{p}-flash-scanner-{k}"}},
                                          {"name": "run", "persistentVolumeClaim": {"claimName": f"{p}-run-scanner-{k}"}}]}})
    docs.append({"apiVersion": "v1", "kind": "Pod",
                 "metadata": {"name": f"{p}-hub", "labels": labels},
                 "spec": {"hostNetwork": True, "restartPolicy": "Never",
                          "containers": [without_ports(hub_container(args.image, f"127.0.0.1:{args.hub_port}", devices))],
                          "volumes": [{"name": "hub-config", "configMap": {"name": f"{p}-hub"}},
                                      {"name": "run", "persistentVolumeClaim": {"claimName": f"{p}-run-hub"}}]}})
    header = (f"# Generated by deploy/kubernetes/render.py podman (scripts/check-fleet.sh): the fleet as\n"
              f"# Pods for `podman kube play`, {args.scanners} scanners on 127.0.0.1:{ports[0][0]}.. and the hub on {args.hub_port}.\n")
    return header, docs


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("target", choices=["kubernetes", "podman"])
    parser.add_argument("--scanners", type=int, default=3, help="how many scanners (1..100, default 3)")
    parser.add_argument("--scene", default=str(pathlib.Path(__file__).resolve().parents[2] / "scenes" / "corridor.yaml"),
                        help="the scene every scanner emulates (default scenes/corridor.yaml)")
    parser.add_argument("--image", default="ldoem:0.1.0", help="the image (default ldoem:0.1.0)")
    parser.add_argument("--prefix", default="ldoem-fleet", help="podman: the names' prefix")
    parser.add_argument("--port-base", type=int, default=49300,
                        help="podman: scanner k on 127.0.0.1:BASE+2k, its LPT bridge on BASE+2k+1")
    parser.add_argument("--hub-port", type=int, default=49299, help="podman: the hub's port")
    parser.add_argument("--out", help="write here instead of stdout")
    args = parser.parse_args()
    if not 1 <= args.scanners <= 100:
        parser.error("--scanners must be 1..100")
    if not 1024 <= args.port_base <= 65535 - 2 * args.scanners or not 1024 <= args.hub_port <= 65535:
        parser.error("ports out of range")
    try:
        scene = pathlib.Path(args.scene).read_text()
    except OSError as error:
        parser.error(f"--scene: {error}")
    header, docs = (kubernetes if args.target == "kubernetes" else podman)(args, scene)
    text = header + "".join("---\n" + "\n".join(dump(doc)) + "\n" for doc in docs)
    if args.out:
        pathlib.Path(args.out).write_text(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
