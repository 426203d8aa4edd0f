#!/usr/bin/env bash
# The Slurm test: starts a real single-node Slurm on localhost from Debian's packages (slurmctld,
# slurmd, munge), renders an 8-frame 96x64 animation with scripts/slurm/submit.sh as an array of
# 3 tasks (frames 0..1, 2..4, 5..7) and the video job after it, waits for both, and checks that
# every frame equals the same frame of one whole `qjulia animate` run byte for byte (cmp), that
# each task rendered its own range, and that the video holds 8 frames of 96x64 (ffprobe). Then
# a path-traced 64x45 still with scripts/slurm/submit-still.sh as an array of 3 tiles (rows
# 0..15, 15..30, 30..45) and the merge job after it, and checks that the merged PNG and EXR
# equal one whole `qjulia render` byte for byte. Before that, without Slurm, it checks
# animate.sbatch's split for many frame and task counts, and still.sbatch's tiles.
#
#   scripts/slurm/test.sh      as root; QJULIA_BIN defaults to target/release/qjulia
#
# - Everything it makes (slurm.conf, the controller's state, slurmd's spool, munge's key, socket,
#   seed, pid and log files, the frames, the jobs' output) is in one `mktemp -d` folder, removed
#   after a pass and kept, with its logs printed, after a failure.
# - A trap on EXIT, whatever happens (INT and TERM included), cancels the jobs, stops slurmd,
#   slurmctld and munged (TERM, then KILL after 10 s), and kills any process left that carries
#   this run's SLURM_CONF (slurmstepd, the jobs' processes), so that nothing holds CI open.
# - It gives up after 5 minutes and fails; it never skips. A missing package is a failure that
#   names it (.ci/run installs them). Without ffmpeg the video is not checked, except under CI
#   (CI=1 or QJULIA_CI=1), where that too is a failure.
# - It prints the wall time at the end: "slurm test: N s".
#
# Slurm 22.05 (Debian 12) as root in a container works with these plain settings:
# - munged in the foreground (as this script's child, its log on stderr) with its own key,
#   socket, pid and seed files. It refuses a socket whose folders are not searchable by all,
#   hence chmod 711 on the mktemp folder (mktemp makes it 0700).
# - AuthType=auth/munge, CredType=cred/munge, AuthInfo=socket=...: the daemons, slurmstepd and
#   the client commands (they read SLURM_CONF) all use that socket.
# - SlurmUser=root, SlurmdUser=root: the daemons run as the user who starts them.
# - ProctrackType=proctrack/linuxproc: finds a job's processes by parent pid in /proc; the cgroup
#   plugin needs a cgroup hierarchy it may write, which a container does not give.
# - TaskPlugin=task/none: no binding to CPUs, no cgroup confinement.
# - AccountingStorageType=accounting_storage/none, JobAcctGatherType=jobacct_gather/none,
#   JobCompType=jobcomp/none: no slurmdbd and no database.
# - SelectType=select/cons_tres, SelectTypeParameters=CR_Core: array tasks share the node, a
#   core each, instead of one job at a time.
# - SlurmctldHost=localhost(127.0.0.1); NodeName=qjulia-test NodeAddr=127.0.0.1 CPUs=$(nproc),
#   and slurmd -N qjulia-test: the node is this machine whatever its hostname.
#   ReturnToService=2: the node is idle as soon as slurmd registers.
# - SlurmctldPort/SlurmdPort: two free ports picked at random, so that another Slurm on the
#   machine is neither used nor disturbed.
# - slurmctld -D -c and slurmd -D: in the foreground as this script's children (their pids are
#   known; no pid-file races), with a fresh state.
# The logs' "mpi/pmix ... can not load PMIx library" errors are harmless (MpiDefault=none).
set -euo pipefail

started=$(date +%s)
deadline=$((started + 300))
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
bin=$(realpath -m -- "${QJULIA_BIN:-$root/target/release/qjulia}")
ci=0
[[ ${CI:-} == 1 || ${CI:-} == true || ${QJULIA_CI:-} == 1 ]] && ci=1
node=qjulia-test
frames=8
tasks=3

fail() {
    echo "slurm test: FAILED: $*" >&2
    exit 1
}
left() { # seconds to the deadline, at least 1 (timeout 0 would mean no limit)
    local s=$((deadline - $(date +%s)))
    echo $((s > 0 ? s : 1))
}

# What it needs, before anything is started.
[[ $(id -u) -eq 0 ]] || fail "needs root (slurmd runs the jobs as root here); run it with sudo"
missing=()
for need in slurmctld:slurmctld slurmd:slurmd munged:munge munge:munge unmunge:munge \
    sbatch:slurm-client scontrol:slurm-client scancel:slurm-client sinfo:slurm-client \
    timeout:coreutils cmp:diffutils; do
    command -v "${need%%:*}" >/dev/null || missing+=("${need#*:} (no ${need%%:*})")
done
((${#missing[@]} == 0)) || fail "missing package: ${missing[*]}; install: apt-get install slurm-wlm slurmctld slurmd munge"
[[ -x $bin ]] || fail "no qjulia binary at $bin: build it (cargo build --release) or set QJULIA_BIN"
video_checked=1
if ! command -v ffmpeg >/dev/null || ! command -v ffprobe >/dev/null; then
    ((ci == 0)) || fail "missing package: ffmpeg (no ffmpeg or ffprobe), needed under CI"
    echo "slurm test: warning: no ffmpeg: the video job will fail and the video is not checked" >&2
    video_checked=0
fi

tmp=$(mktemp -d /tmp/qjulia-slurm-test.XXXXXX)
chmod 711 "$tmp"
mkdir -p "$tmp"/{munge,state,spool,log,jobs}
conf=$tmp/slurm.conf
pids=() # the daemons, in the order they are stopped: slurmd, slurmctld, munged
jobs=() # the submitted job ids

cleanup() {
    local rc=$? pid gone stale leftover=()
    trap - EXIT INT TERM
    set +e
    if ((rc != 0 && ${#jobs[@]} > 0)); then
        echo "==== the jobs" >&2
        timeout 10 scontrol -o show job 2>&1 |
            grep -oE '^JobId=[0-9]+|ArrayTaskId=[^ ]+|JobState=[^ ]+|Reason=[^ ]+|ExitCode=[^ ]+' |
            paste -sd ' ' | sed 's/ JobId=/\nJobId=/g' >&2
    fi
    if ((${#jobs[@]} > 0)) && timeout 10 scancel "${jobs[@]}" >/dev/null 2>&1; then
        for _ in $(seq 20); do # up to 10 s for the jobs to end, so that slurmd stops at once
            [[ -z $(timeout 5 squeue -h -o %i 2>/dev/null) ]] && break
            sleep 0.5
        done
    fi
    for pid in "${pids[@]}"; do
        kill -TERM "$pid" 2>/dev/null
    done
    for pid in "${pids[@]}"; do
        gone=0
        for _ in $(seq 100); do
            kill -0 "$pid" 2>/dev/null || {
                gone=1
                break
            }
            sleep 0.1
        done
        ((gone)) || kill -KILL "$pid" 2>/dev/null
        wait "$pid" 2>/dev/null
    done
    # slurmstepd and the jobs' processes outlive slurmd; they carry this run's SLURM_CONF.
    unset SLURM_CONF
    mapfile -t stale < <(grep -lzxF "SLURM_CONF=$conf" /proc/[0-9]*/environ 2>/dev/null | cut -d/ -f3)
    for pid in "${stale[@]}"; do
        if [[ $pid != "$$" ]] && kill -KILL "$pid" 2>/dev/null; then
            leftover+=("$pid")
        fi
    done
    if ((${#leftover[@]} > 0)); then
        echo "slurm test: killed processes left by the jobs: ${leftover[*]}" >&2
    fi
    if ((rc != 0)); then
        local log
        for log in "$tmp"/log/* "$tmp"/jobs/*; do
            [[ -f $log ]] || continue
            echo "==== $log" >&2
            tail -n 60 "$log" >&2
        done
        echo "slurm test: FAILED after $(($(date +%s) - started)) s; its folder is kept: $tmp" >&2
    else
        rm -rf "$tmp"
        echo "slurm test: $(($(date +%s) - started)) s"
    fi
    exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# Waits until "$@" succeeds, checking that the daemons are alive; fails at the deadline.
wait_until() {
    local what=$1 pid
    shift
    until "$@" >/dev/null 2>&1; do
        for pid in "${pids[@]}"; do
            kill -0 "$pid" 2>/dev/null || fail "a daemon (pid $pid) died while waiting for $what"
        done
        (($(date +%s) < deadline)) || fail "gave up after 5 minutes waiting for $what"
        sleep 0.5
    done
}

# 1. animate.sbatch's split, without Slurm: for N frames and T tasks, the tasks' ranges in order
#    are contiguous, cover 0..N-1 once, and differ in length by at most one.
stub=$tmp/stub-qjulia
# shellcheck disable=SC2016 # $5 is the stub's
printf '#!/bin/sh\necho "$5"\n' >"$stub" # animate --scene S --frames A..B ...: prints A..B
chmod +x "$stub"
for n in 1 7 8 120; do
    for t in 1 3 8 9 16; do
        next=0 min_len=$n max_len=0
        for ((k = 0; k < t; k++)); do
            range=$(QJULIA_BIN=$stub QJULIA_SCENE=s QJULIA_OUT=o QJULIA_FRAMES=$n \
                SLURM_ARRAY_TASK_ID=$((k + 5)) SLURM_ARRAY_TASK_MIN=5 \
                SLURM_ARRAY_TASK_MAX=$((t + 4)) SLURM_ARRAY_TASK_COUNT=$t \
                "$here/animate.sbatch" | tail -n 1) || fail "animate.sbatch failed for task $k of $t, $n frames"
            if [[ $range == *"no frames"* ]]; then
                len=0
            else
                [[ $range == "$next.."* ]] || fail "task $k of $t, $n frames: '$range' does not start at $next"
                len=$((${range#*..} - next + 1))
                next=$((next + len))
            fi
            if ((len < min_len)); then min_len=$len; fi
            if ((len > max_len)); then max_len=$len; fi
        done
        ((next == n)) || fail "$t tasks, $n frames: the ranges end at $((next - 1)), not $((n - 1))"
        ((max_len - min_len <= 1)) || fail "$t tasks, $n frames: ranges of $min_len to $max_len frames"
    done
done
echo "slurm test: animate.sbatch's split is contiguous and even"

# still.sbatch's tiles, without Slurm: array task ID k + 5 of T renders tile k/T into
# PARTS/tile-k-of-T.exr; its merge job merges the T parts, in order, with the tiles' --backend.
stub_all=$tmp/stub-qjulia-all
printf '#!/bin/sh\necho "$*"\n' >"$stub_all" # prints its arguments
chmod +x "$stub_all"
for t in 1 3 7; do
    for ((k = 0; k < t; k++)); do
        line=$(QJULIA_BIN=$stub_all QJULIA_SCENE=s QJULIA_PARTS=$tmp/p QJULIA_OPTS="--backend gpu" \
            SLURM_ARRAY_TASK_ID=$((k + 5)) SLURM_ARRAY_TASK_MIN=5 \
            SLURM_ARRAY_TASK_MAX=$((t + 4)) SLURM_ARRAY_TASK_COUNT=$t \
            "$here/still.sbatch" | tail -n 1) || fail "still.sbatch failed for task $k of $t"
        [[ $line == "render --scene s --backend gpu --tile $k/$t --hdr $tmp/p/tile-$k-of-$t.exr" ]] ||
            fail "still.sbatch task $k of $t ran: $line"
    done
    want="merge"
    for ((k = 0; k < t; k++)); do want+=" $tmp/p/tile-$k-of-$t.exr"; done
    line=$(QJULIA_BIN=$stub_all QJULIA_STEP=merge QJULIA_PARTS=$tmp/p QJULIA_TASKS=$t \
        QJULIA_PNG=o.png QJULIA_OPTS="--set image.samples=2 --backend gpu" \
        "$here/still.sbatch" | tail -n 1) || fail "still.sbatch's merge failed for $t tiles"
    [[ $line == "$want -o o.png --backend gpu" ]] || fail "still.sbatch's merge of $t tiles ran: $line"
done
echo "slurm test: still.sbatch renders tile k/T in task k and merges the T tiles in order"

# 2. The reference: one whole run, no split.
cat >"$tmp/scene.toml" <<EOF
[image]
width = 96
height = 64

[animation]
frames = $frames
path_radius = 0.25
EOF
timeout "$(left)" "$bin" animate --scene "$tmp/scene.toml" --out "$tmp/whole" 2>"$tmp/log/whole.log" ||
    fail "the whole run failed (log: $tmp/log/whole.log)"

# The still's reference: one whole path-traced render.
cat >"$tmp/still.toml" <<EOF
[image]
width = 64
height = 45
samples = 4

[shading]
model = "path"
EOF
timeout "$(left)" "$bin" render --scene "$tmp/still.toml" -o "$tmp/whole-still.png" \
    --hdr "$tmp/whole-still.exr" 2>"$tmp/log/whole-still.log" ||
    fail "the whole still failed (log: $tmp/log/whole-still.log)"

# 3. munge, slurmctld, slurmd.
dd if=/dev/urandom of="$tmp/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$tmp/munge/munge.key"
munged --foreground --socket="$tmp/munge/munge.socket" --key-file="$tmp/munge/munge.key" \
    --pid-file="$tmp/munge/munged.pid" --seed-file="$tmp/munge/munged.seed" \
    >"$tmp/log/munged.log" 2>&1 &
pids=("$!")
munge_works() { munge -n -S "$tmp/munge/munge.socket" | unmunge -S "$tmp/munge/munge.socket"; }
wait_until "munged" munge_works

port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
pick_port() {
    local port
    while :; do
        port=$((20000 + RANDOM % 20000))
        [[ $port != "${1:-}" ]] && port_free "$port" && break
    done
    echo "$port"
}
ctld_port=$(pick_port)
slurmd_port=$(pick_port "$ctld_port")
cat >"$conf" <<EOF
ClusterName=qjulia-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$tmp/munge/munge.socket
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MailProg=/bin/true
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$conf
slurmctld -D -c >"$tmp/log/slurmctld.out" 2>&1 &
pids=("$!" "${pids[@]}")
wait_until "slurmctld" timeout 10 scontrol ping
slurmd -D -N "$node" >"$tmp/log/slurmd.out" 2>&1 &
pids=("$!" "${pids[@]}")
node_idle() { [[ $(timeout 10 sinfo -h -N -n "$node" -o %T) == idle ]]; }
wait_until "the node to be idle" node_idle
echo "slurm test: Slurm is up ($(($(date +%s) - started)) s)"

# 4. The array and the video job, by submit.sh as a user would.
cd "$tmp"
submitted=$(QJULIA_BIN=$bin \
    QJULIA_ARRAY_OPTS="--output=$tmp/jobs/array-%A_%a.out" \
    QJULIA_VIDEO_OPTS="--output=$tmp/jobs/video-%j.out" \
    timeout 60 "$here/submit.sh" "$tmp/scene.toml" "$tmp/split" "$tmp/video.mp4" "$tasks") ||
    fail "submit.sh failed"
echo "$submitted"
array=$(sed -n 's/^array job \([0-9]*\):.*/\1/p' <<<"$submitted")
video=$(sed -n 's/^video job \([0-9]*\):.*/\1/p' <<<"$submitted")
[[ -n $array && -n $video ]] || fail "submit.sh printed no job ids"
jobs=("$array" "$video")

# The states of a job's records (one per array task once they run), one a line.
states() { timeout 10 scontrol -o show job "$1" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2; }
finished() { # the video job has ended, or an array task has failed
    local a v
    a=$(states "$array") || return 1
    v=$(states "$video") || return 1
    if grep -qvE '^(PENDING|CONFIGURING|RUNNING|COMPLETING|COMPLETED)$' <<<"$a"; then
        return 0
    fi
    case $v in
    PENDING | CONFIGURING | RUNNING | COMPLETING | REQUEUED | RESIZING | SUSPENDED) return 1 ;;
    *) return 0 ;;
    esac
}
wait_until "the jobs to finish" finished
echo "slurm test: the jobs finished ($(($(date +%s) - started)) s)"

array_states=$(states "$array" | sort | uniq -c | sed "s/^ *//" | paste -sd, -)
[[ $array_states == "$tasks COMPLETED" ]] || fail "array job $array: $array_states (wanted $tasks COMPLETED)"
want_video=COMPLETED
((video_checked)) || want_video=FAILED
[[ $(states "$video") == "$want_video" ]] || fail "video job $video: $(states "$video") (wanted $want_video)"

# 5. Each task rendered its own range (8 frames in 3 tasks: 0..1, 2..4, 5..7).
ranges=(0..1 2..4 5..7)
for ((k = 0; k < tasks; k++)); do
    grep -q "^qjulia task $k of $tasks: frames ${ranges[k]} of $frames " "$tmp/jobs/array-${array}_$k.out" ||
        fail "task $k's output does not say frames ${ranges[k]}"
done

# 6. The frames, byte for byte.
names() { find "$1" -mindepth 1 -printf '%f\n' | sort; }
expected=$(names "$tmp/whole")
[[ $expected == "$(printf 'frame-%05d.png\n' $(seq 0 $((frames - 1))))" ]] ||
    fail "the whole run wrote: $expected"
[[ $(names "$tmp/split") == "$expected" ]] ||
    fail "the array wrote: $(names "$tmp/split" | tr '\n' ' ')"
for f in $expected; do
    cmp "$tmp/whole/$f" "$tmp/split/$f" || fail "$f differs from the whole run's"
done
echo "slurm test: the $frames frames of $tasks tasks equal the whole run's, byte for byte"

# 7. The video.
if ((video_checked)); then
    probe=$(ffprobe -v error -count_frames -select_streams v:0 \
        -show_entries stream=width,height,nb_read_frames -of default=noprint_wrappers=1 \
        "$tmp/video.mp4") || fail "ffprobe cannot read $tmp/video.mp4"
    [[ $probe == *"width=96"* && $probe == *"height=64"* && $probe == *"nb_read_frames=$frames"* ]] ||
        fail "the video is not $frames frames of 96x64: $(tr '\n' ' ' <<<"$probe")"
    echo "slurm test: the video holds $frames frames of 96x64"
fi

# 8. The still: 3 tiles and the merge, by submit-still.sh as a user would.
submitted=$(QJULIA_BIN=$bin QJULIA_HDR=$tmp/still.exr \
    QJULIA_ARRAY_OPTS="--output=$tmp/jobs/tile-%A_%a.out" \
    QJULIA_MERGE_OPTS="--output=$tmp/jobs/merge-%j.out" \
    timeout 60 "$here/submit-still.sh" "$tmp/still.toml" "$tmp/parts" "$tmp/still.png" "$tasks") ||
    fail "submit-still.sh failed"
echo "$submitted"
tiles=$(sed -n 's/^array job \([0-9]*\):.*/\1/p' <<<"$submitted")
merge=$(sed -n 's/^merge job \([0-9]*\):.*/\1/p' <<<"$submitted")
[[ -n $tiles && -n $merge ]] || fail "submit-still.sh printed no job ids"
jobs+=("$tiles" "$merge")
still_finished() { # the merge job has ended, or a tile has failed
    local a m
    a=$(states "$tiles") || return 1
    m=$(states "$merge") || return 1
    if grep -qvE '^(PENDING|CONFIGURING|RUNNING|COMPLETING|COMPLETED)$' <<<"$a"; then
        return 0
    fi
    case $m in
    PENDING | CONFIGURING | RUNNING | COMPLETING | REQUEUED | RESIZING | SUSPENDED) return 1 ;;
    *) return 0 ;;
    esac
}
wait_until "the still's jobs to finish" still_finished
echo "slurm test: the still's jobs finished ($(($(date +%s) - started)) s)"
tile_states=$(states "$tiles" | sort | uniq -c | sed "s/^ *//" | paste -sd, -)
[[ $tile_states == "$tasks COMPLETED" ]] || fail "tile array job $tiles: $tile_states (wanted $tasks COMPLETED)"
[[ $(states "$merge") == COMPLETED ]] || fail "merge job $merge: $(states "$merge") (wanted COMPLETED)"
for ((k = 0; k < tasks; k++)); do
    grep -q "^qjulia task $k of $tasks: tile $k/$tasks " "$tmp/jobs/tile-${tiles}_$k.out" ||
        fail "tile task $k's output does not say tile $k/$tasks"
done
[[ $(names "$tmp/parts") == "$(printf "tile-%d-of-$tasks.exr\n" $(seq 0 $((tasks - 1))))" ]] ||
    fail "the tiles wrote: $(names "$tmp/parts" | tr '\n' ' ')"
cmp "$tmp/whole-still.png" "$tmp/still.png" || fail "the merged still's PNG differs from one render's"
cmp "$tmp/whole-still.exr" "$tmp/still.exr" || fail "the merged still's EXR differs from one render's"
echo "slurm test: the path-traced still of $tasks tiles equals one render, byte for byte (PNG and EXR)"
