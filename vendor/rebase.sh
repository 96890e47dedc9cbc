#!/usr/bin/env bash
# Re-applies gymfleet's patches to a vendored crate onto another release of it, in the
# order they were committed, and optionally runs their tests there.
#
#   bash vendor/rebase.sh rapier3d 0.37.0            # apply onto 0.37.0 in a scratch tree
#   bash vendor/rebase.sh rapier3d 0.37.0 --test     # ... then run Rapier's own tests there
#   bash vendor/rebase.sh rapier3d 0.36.1            # self-check: must rebuild vendor/ exactly
#
# How: the release comes from the crates registry through cargo (`cargo fetch` of a
# throw-away crate, so the configured registry or mirror is used). The scratch tree
# (target/rebase/<crate>-<version>, a git repository that borrows this one's objects) starts
# as the pristine release; every commit of this repository that changed vendor/<crate>
# after the one that added it is applied in turn with `git apply --3way`, and committed
# there with its message. The first patch that does not apply stops the run, naming the
# commit and the PATCHES.md sections it mentions; resolve it in the scratch tree
# (`git status` there), commit, and re-run with --from <next commit> to go on.
#
# On success: with the same version, the scratch tree must equal vendor/<crate> (checked).
# With another, copy it over vendor/<crate> (keep PATCHES.md), update `[patch.crates-io]`
# and the lock file, then run what PATCHES.md's "How they are checked" lists: gymfleet's
# physics tests (cargo test -p gymfleet-env), the differential check
# (vendor/<crate>-diffcheck) and the crate's own tests (--test runs those named below).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD

CRATE=${1:?usage: vendor/rebase.sh CRATE VERSION [--test] [--from COMMIT]}
VERSION=${2:?usage: vendor/rebase.sh CRATE VERSION [--test] [--from COMMIT]}
shift 2
RUN_TESTS=0
FROM=""
while [[ $# -gt 0 ]]; do
    case $1 in
        --test) RUN_TESTS=1 ;;
        --from) FROM=${2:?--from needs a commit}; shift ;;
        *) echo "unknown argument: $1" >&2; exit 2 ;;
    esac
    shift
done
VENDORED=vendor/$CRATE
[[ -f $VENDORED/Cargo.toml ]] || { echo "no vendored crate at $VENDORED" >&2; exit 2; }

# The commit that added the vendored copy (the pristine release the patches start from).
BASE=$(git log --diff-filter=A --format=%H -- "$VENDORED/Cargo.toml" | tail -1)
COMMITS=$(git log --reverse --format=%H "$BASE".. -- "$VENDORED")

fetch_release() { # prints the path of CRATE-VERSION's sources in cargo's registry
    local probe=$ROOT/target/rebase/fetch
    rm -rf "$probe"
    mkdir -p "$probe/src"
    printf '[package]\nname = "rebase-fetch"\nversion = "0.0.0"\nedition = "2021"\n[workspace]\n[dependencies]\n%s = "=%s"\n' \
        "$CRATE" "$VERSION" >"$probe/Cargo.toml"
    : >"$probe/src/lib.rs"
    (cd "$probe" && cargo fetch --quiet) >&2
    local src
    src=$(ls -d "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/"$CRATE-$VERSION" | head -1)
    [[ -d $src ]] || { echo "cargo fetched no $CRATE $VERSION" >&2; exit 1; }
    echo "$src"
}

TREE=$ROOT/target/rebase/$CRATE-$VERSION
if [[ -z $FROM ]]; then
    SRC=$(fetch_release)
    rm -rf "$TREE"
    mkdir -p "$TREE"
    cp -r "$SRC/." "$TREE/"
    rm -f "$TREE/.cargo_vcs_info.json" "$TREE/.cargo-ok"
    git -C "$TREE" init -q
    # Borrow this repository's objects, so that --3way finds every patch's preimage.
    echo "$ROOT/.git/objects" >"$TREE/.git/objects/info/alternates"
    git -C "$TREE" add -A
    git -C "$TREE" -c user.name=rebase -c user.email=rebase@localhost commit -q -m "$CRATE $VERSION as published"
fi

applied=0
skipping=${FROM:+1}
for commit in $COMMITS; do
    if [[ -n $skipping ]]; then
        [[ $commit == "$FROM"* ]] && skipping="" || continue
    fi
    # Cargo.lock is generated (by running the crate's tests there), not a patch.
    diff=$(git diff "$commit^" "$commit" --relative="$VENDORED" -- "$VENDORED" ":(exclude)$VENDORED/Cargo.lock")
    [[ -n $diff ]] || continue
    subject=$(git log -1 --format=%s "$commit")
    if ! printf '%s\n' "$diff" | git -C "$TREE" apply --3way --whitespace=nowarn 2>"$TREE.apply.log"; then
        cat "$TREE.apply.log" >&2
        sections=$(git log -1 --format=%B "$commit" | grep -o -E '[Pp]atch(es)? [0-9]+' | sort -u | tr '\n' ' ' || true)
        echo "FAILED at $commit: $subject" >&2
        echo "  (mentions: ${sections:-no patch number})" >&2
        echo "  resolve in $TREE (git status), commit, then: bash vendor/rebase.sh $CRATE $VERSION --from <the next commit>" >&2
        exit 1
    fi
    git -C "$TREE" add -A
    git -C "$TREE" -c user.name=rebase -c user.email=rebase@localhost commit -q --allow-empty -m "$subject" -m "from $commit"
    applied=$((applied + 1))
done
echo "applied $applied commits of $VENDORED onto $CRATE $VERSION in $TREE"

if [[ $VERSION == $(sed -n 's/^version = "\(.*\)"/\1/p' "$VENDORED/Cargo.toml" | head -1) ]]; then
    # The same release: the result must be the vendored copy, file for file.
    if diff -r -q -x .git -x target -x Cargo.lock -x '*.apply.log' -x .cargo_vcs_info.json -x .cargo-ok "$TREE" "$VENDORED"; then
        echo "self-check: the patches rebuild $VENDORED exactly"
    else
        echo "self-check FAILED: the rebuilt tree differs from $VENDORED (above)" >&2
        exit 1
    fi
fi

if [[ $RUN_TESTS == 1 && $CRATE != rapier3d ]]; then
    (cd "$TREE" && cargo test --lib)
elif [[ $RUN_TESTS == 1 ]]; then
    # Rapier's own tests that the patches touch (PATCHES.md, "How they are checked").
    (cd "$TREE" && cargo test --lib --test multibody_armature --test multibody_coupling \
        --test multibody_coupling_topology --test multibody_dof_inertia --test multibody_spring \
        --test multibody_kinematics_reuse --test joint_stability --test issue_968_multibody_weld_settle)
fi
