"""Checks what the JSON schemas cannot: that rendered gymfleet manifests keep the
fleet's invariants. Usage: check_manifests.py RENDERED.yaml [MORE.yaml ...]

- the StatefulSet starts pods in parallel and names a headless Service
  (clusterIP: None, not publishing unready pods) that selects its pods;
- every server container probes gRPC health on its gRPC port (readiness and liveness),
  derives GYMFLEET_THREADS from its CPU limit (or sets it equal), has CPU and memory
  limits, and runs non-root with a read-only root filesystem and no capabilities;
- GYMFLEET_LISTEN listens on all interfaces on the probed port;
- GYMFLEET_POOL_NICENESS, where set, is a niceness the server takes (0..19);
- GYMFLEET_MAX_ENVS fits the memory limit at the measured ~55 KB per 2-DOF arm;
- the grace period covers the drain, and a PodDisruptionBudget allows one pod down;
- GYMFLEET_METRICS_LISTEN listens on all interfaces on the container port named
  `metrics`, the pod's prometheus.io annotations point there, the headless Service
  exposes it, and every ServiceMonitor selects that Service, scrapes that port and carries
  the `release` label a Prometheus's serviceMonitorSelector matches;
- every namespace an object is rendered into is rendered as a Namespace too;
- a startupProbe holds liveness off for a start that reads a model library;
- with TLS on, the probes target the plaintext health listener (GYMFLEET_HEALTH_LISTEN,
  the container port named `health`), which the kubelet's gRPC probe can reach;
- tokens need TLS, and certificates, keys and tokens come from Secret volumes mounted
  read-only;
- with tokens on, a NetworkPolicy admits the metrics port (no token of its own) only from
  named sources.

Exits 1 with one line per broken rule.
"""

import math
import sys

import yaml

BYTES_PER_ENV = 55_000  # measured for models/arm2.json; see k8s/base/configmap.yaml
MIN_GRACE_SECONDS = 30
GRPC_PORT = 50051
# The startup window (failureThreshold x periodSeconds) a server gets to read, convert and
# check its settings and model library before liveness counts: see k8s/base/statefulset.yaml.
MIN_STARTUP_SECONDS = 300
SECRET_FILES = ("GYMFLEET_TLS_CERT", "GYMFLEET_TLS_KEY", "GYMFLEET_TLS_CLIENT_CA", "GYMFLEET_AUTH_TOKENS")

UNITS = {"Ki": 2**10, "Mi": 2**20, "Gi": 2**30, "Ti": 2**40, "k": 10**3, "M": 10**6, "G": 10**9, "T": 10**12}


def quantity(text):
    """A Kubernetes quantity ("3Gi", "1500m", "2") as a number."""
    text = str(text)
    if text.endswith("m"):
        return float(text[:-1]) / 1000
    for suffix, factor in UNITS.items():
        if text.endswith(suffix):
            return float(text[: -len(suffix)]) * factor
    return float(text)


def selects(selector, labels):
    return all(labels.get(k) == v for k, v in (selector or {}).items())


def check(docs):
    errors = []
    fail = errors.append
    by_kind = {}
    for doc in docs:
        by_kind.setdefault(doc.get("kind"), []).append(doc)
    config = {}
    for cm in by_kind.get("ConfigMap", []):
        config.update(cm.get("data") or {})

    sets = by_kind.get("StatefulSet", [])
    if not sets:
        fail("no StatefulSet rendered")
    for sts in sets:
        name = sts["metadata"]["name"]
        spec = sts["spec"]
        pod_labels = spec["template"]["metadata"].get("labels", {})
        if spec.get("podManagementPolicy") != "Parallel":
            fail(f"statefulset/{name}: podManagementPolicy must be Parallel")
        services = [s for s in by_kind.get("Service", []) if s["metadata"]["name"] == spec.get("serviceName")]
        if not services:
            fail(f"statefulset/{name}: serviceName {spec.get('serviceName')!r} is not a rendered Service")
        for svc in services:
            sspec = svc["spec"]
            if sspec.get("clusterIP") != "None":
                fail(f"service/{svc['metadata']['name']}: must be headless (clusterIP: None)")
            if sspec.get("publishNotReadyAddresses", False):
                fail(f"service/{svc['metadata']['name']}: must not publish unready pods")
            if not selects(sspec.get("selector"), pod_labels):
                fail(f"service/{svc['metadata']['name']}: selector does not match statefulset/{name}'s pods")
        pdbs = [p for p in by_kind.get("PodDisruptionBudget", []) if selects(p["spec"]["selector"].get("matchLabels"), pod_labels)]
        if not pdbs:
            fail(f"statefulset/{name}: no PodDisruptionBudget selects its pods")
        for pdb in pdbs:
            if pdb["spec"].get("maxUnavailable") != 1:
                fail(f"poddisruptionbudget/{pdb['metadata']['name']}: maxUnavailable must be 1")

        pod = spec["template"]["spec"]
        if pod.get("terminationGracePeriodSeconds", 30) < MIN_GRACE_SECONDS:
            fail(f"statefulset/{name}: terminationGracePeriodSeconds below {MIN_GRACE_SECONDS}")
        if not (pod.get("securityContext") or {}).get("runAsNonRoot"):
            fail(f"statefulset/{name}: pod securityContext.runAsNonRoot must be true")
        for c in pod["containers"]:
            where = f"statefulset/{name} container {c['name']}"
            sc = c.get("securityContext") or {}
            if not sc.get("readOnlyRootFilesystem"):
                fail(f"{where}: readOnlyRootFilesystem must be true")
            if sc.get("allowPrivilegeEscalation", True):
                fail(f"{where}: allowPrivilegeEscalation must be false")
            if "ALL" not in ((sc.get("capabilities") or {}).get("drop") or []):
                fail(f"{where}: capabilities must drop ALL")
            limits = (c.get("resources") or {}).get("limits") or {}
            if "cpu" not in limits or "memory" not in limits:
                fail(f"{where}: cpu and memory limits are required")
                continue
            env = {e["name"]: e for e in c.get("env", [])}
            values = dict(config)
            values.update({k: e["value"] for k, e in env.items() if "value" in e})
            threads = env.get("GYMFLEET_THREADS")
            ref = ((threads or {}).get("valueFrom") or {}).get("resourceFieldRef") or {}
            cpus = math.ceil(quantity(limits["cpu"]))
            if ref:
                if ref.get("resource") != "limits.cpu" or quantity(ref.get("divisor", "1")) != 1:
                    fail(f"{where}: GYMFLEET_THREADS must come from limits.cpu with divisor 1")
            elif threads is None or int(values.get("GYMFLEET_THREADS", 0)) != cpus:
                fail(f"{where}: GYMFLEET_THREADS must equal the CPU limit ({cpus})")
            niceness = str(values.get("GYMFLEET_POOL_NICENESS", "0"))
            if not niceness.isdigit() or int(niceness) > 19:
                fail(f"{where}: GYMFLEET_POOL_NICENESS must be 0..19, got {niceness!r}")
            check_probes(c, values, where, fail)
            check_secrets(c, pod, values, where, fail)
            if values.get("GYMFLEET_AUTH_TOKENS"):
                check_metrics_policy(by_kind, pod_labels, c, name, fail)
            if values.get("GYMFLEET_LISTEN") != f"0.0.0.0:{GRPC_PORT}":
                fail(f"{where}: GYMFLEET_LISTEN must be 0.0.0.0:{GRPC_PORT}")
            metrics_port = port_named(c, "metrics")
            if metrics_port is None or values.get("GYMFLEET_METRICS_LISTEN") != f"0.0.0.0:{metrics_port}":
                fail(f"{where}: GYMFLEET_METRICS_LISTEN must be 0.0.0.0:<the port named metrics>")
            annotations = spec["template"]["metadata"].get("annotations") or {}
            if annotations.get("prometheus.io/port") != str(metrics_port) or annotations.get("prometheus.io/path") != "/metrics":
                fail(f"statefulset/{name}: prometheus.io annotations must name the metrics port and /metrics")
            for svc in services:
                if not any(p.get("name") == "metrics" and p.get("targetPort") == "metrics" for p in svc["spec"].get("ports", [])):
                    fail(f"service/{svc['metadata']['name']}: must expose the port named metrics")
            for sm in by_kind.get("ServiceMonitor", []):
                where_sm = f"servicemonitor/{sm['metadata']['name']}"
                if not any(selects(sm["spec"]["selector"].get("matchLabels"), s["metadata"].get("labels", {})) for s in services):
                    fail(f"{where_sm}: selector does not match the headless Service")
                if [e.get("port") for e in sm["spec"].get("endpoints", [])] != ["metrics"]:
                    fail(f"{where_sm}: must scrape the Service port named metrics")
                release = (sm["metadata"].get("labels") or {}).get("release")
                if not release or release == "PLACEHOLDER":
                    fail(f"{where_sm}: must carry the `release` label its Prometheus selects (set it in release-label.yaml), got {release!r}")
            library = values.get("GYMFLEET_MODELS")
            if library:
                mounts = [m for m in c.get("volumeMounts", []) if m.get("mountPath") == library]
                volumes = {v["name"]: v for v in pod.get("volumes", [])}
                if not mounts:
                    fail(f"{where}: GYMFLEET_MODELS={library} is not a mounted volume")
                for m in mounts:
                    if not m.get("readOnly"):
                        fail(f"{where}: the model library at {library} must be mounted readOnly")
                    if m.get("name") not in volumes:
                        fail(f"{where}: volumeMount {m.get('name')!r} names no pod volume")
            max_envs = int(values.get("GYMFLEET_MAX_ENVS", 0))
            memory = quantity(limits["memory"])
            if max_envs == 0 or max_envs * BYTES_PER_ENV > memory * 0.8:
                fail(
                    f"{where}: GYMFLEET_MAX_ENVS={max_envs} does not fit {limits['memory']} "
                    f"at {BYTES_PER_ENV} bytes per env with 20% headroom"
                )
    check_namespaces(docs, fail)
    return errors


def port_named(container, name):
    return next((p["containerPort"] for p in container.get("ports", []) if p.get("name") == name), None)


def check_probes(c, values, where, fail):
    """gRPC probes on the port the kubelet can reach: the gRPC port in plaintext, the
    plaintext health listener with TLS on; a startup window for the model library."""
    port = GRPC_PORT
    if values.get("GYMFLEET_TLS_CERT"):
        health = port_named(c, "health")
        if health is None or health == GRPC_PORT or values.get("GYMFLEET_HEALTH_LISTEN") != f"0.0.0.0:{health}":
            fail(f"{where}: with TLS on, GYMFLEET_HEALTH_LISTEN must be 0.0.0.0:<the port named health>, not the TLS port")
        port = health
    for probe in ("startupProbe", "readinessProbe", "livenessProbe"):
        grpc = (c.get(probe) or {}).get("grpc")
        if not grpc or grpc.get("port") != port:
            fail(f"{where}: {probe} must be a grpc probe on port {port}" + (" (TLS is on: the health port)" if port != GRPC_PORT else ""))
    startup = c.get("startupProbe") or {}
    window = startup.get("failureThreshold", 3) * startup.get("periodSeconds", 10)
    if window < MIN_STARTUP_SECONDS:
        fail(f"{where}: startupProbe allows {window} s (failureThreshold x periodSeconds); a start that reads a model library needs {MIN_STARTUP_SECONDS}")


def check_secrets(c, pod, values, where, fail):
    """Tokens only over TLS; certificates, keys and tokens from Secrets, read-only."""
    if values.get("GYMFLEET_AUTH_TOKENS") and not values.get("GYMFLEET_TLS_CERT"):
        fail(f"{where}: GYMFLEET_AUTH_TOKENS without TLS sends tokens in plaintext")
    volumes = {v["name"]: v for v in pod.get("volumes", [])}
    for var in SECRET_FILES:
        path = values.get(var)
        if not path:
            continue
        mounts = [m for m in c.get("volumeMounts", []) if path.startswith(m.get("mountPath", "").rstrip("/") + "/")]
        if not mounts:
            fail(f"{where}: {var}={path} is not in a mounted volume")
        for m in mounts:
            if not m.get("readOnly"):
                fail(f"{where}: {var}={path} must be mounted readOnly")
            secret = volumes.get(m.get("name"), {}).get("secret")
            if secret is None:
                fail(f"{where}: {var}={path} must come from a Secret volume")
                continue
            # Secret files are root-owned: without world read (mode 0444, default 0644),
            # the non-root server reads them only through its group, fsGroup.
            mode = secret.get("defaultMode", 0o644)
            group = (pod.get("securityContext") or {}).get("fsGroup")
            if not mode & 0o004 and group is None:
                fail(f"{where}: {var}={path} is mode {mode:o} without fsGroup: the non-root server cannot read it")


def check_metrics_policy(by_kind, pod_labels, c, name, fail):
    """The metrics port has no token: with tokens on, a NetworkPolicy must admit it only
    from named sources."""
    metrics = port_named(c, "metrics")
    policies = [
        p for p in by_kind.get("NetworkPolicy", [])
        if selects(p["spec"].get("podSelector", {}).get("matchLabels"), pod_labels)
        and "Ingress" in p["spec"].get("policyTypes", ["Ingress"])
    ]
    if not policies:
        fail(f"statefulset/{name}: tokens are on but no NetworkPolicy guards the metrics port (it has no token)")
    for policy in policies:
        for rule in policy["spec"].get("ingress") or []:
            ports = rule.get("ports")
            admits = not ports or any(p.get("port") in (None, "metrics", metrics) for p in ports)
            if admits and not rule.get("from"):
                fail(f"networkpolicy/{policy['metadata']['name']}: admits the metrics port from anywhere; name its sources (`from`)")


def check_namespaces(docs, fail):
    """An overlay that renders into a namespace creates it (or renders none: the current one)."""
    created = {d["metadata"]["name"] for d in docs if d.get("kind") == "Namespace"}
    for d in docs:
        ns = d.get("metadata", {}).get("namespace")
        if ns and ns not in created:
            fail(f"{d['kind'].lower()}/{d['metadata']['name']}: namespace {ns!r} is not created by the overlay (add a Namespace)")


def main(paths):
    docs = []
    for path in paths:
        with open(path, encoding="utf-8") as f:
            docs.extend(d for d in yaml.safe_load_all(f) if d)
    errors = check(docs)
    for error in errors:
        print(f"ERROR {error}")
    if errors:
        return 1
    print(f"policy: {len(docs)} objects in {', '.join(paths)} keep the fleet's invariants")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
