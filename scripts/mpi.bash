# Shared by the scripts that shard work over MPI ranks (scripts/run --ranks,
# scripts/false_alarm_study --ranks): start K ranks on this host under mpirun and name a rank
# that dies. Source it, then call mpi_run.

# mpi_rank, mpi_size: this process's rank and the number of ranks, from the launcher's
# environment (OpenMPI's mpirun or Slurm's srun); 0 and 1 outside a launcher.
mpi_rank() { echo "${OMPI_COMM_WORLD_RANK:-${PMIX_RANK:-${SLURM_PROCID:-0}}}"; }
mpi_size() { echo "${OMPI_COMM_WORLD_SIZE:-${SLURM_NTASKS:-1}}"; }
# mpi_rank_exec COMMAND...: replace this shell with COMMAND, this rank's number and the number of
# ranks appended as its last two arguments (so that no other program reads the launchers'
# variables itself).
mpi_rank_exec() { exec "$@" "$(mpi_rank)" "$(mpi_size)"; }
MPI_PREFIX=()

# mpi_run K LOG DESCRIBE COMMAND...: run COMMAND as K ranks on this host, its output in LOG
# (mpirun itself prefixed by the array MPI_PREFIX, if set: e.g. setpriv --pdeathsig KILL --).
# Returns 0 on success. Otherwise sets MPI_FAILURE to a message: for a rank killed outright,
# "MPI rank R on HOST (WHAT) was killed by signal S (NAME)", WHAT from the function DESCRIBE
# called with R (e.g. the rank's realization range); else the last lines of LOG.
mpi_run() {
  local k=$1 log=$2 describe=$3
  shift 3
  MPI_FAILURE=""
  command -v mpirun >/dev/null || { MPI_FAILURE="mpirun not found (Debian packages openmpi-bin and libopenmpi-dev; scripts/setup installs them)"; return 1; }
  # mpirun as root needs these; more ranks than cores share them; shared-memory transport
  # without the kernel's cross-memory attach (not allowed in every container).
  if [[ $(id -u) == 0 ]]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
  export OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1
  # Under the sanitizers (scripts/sanitize sets ASAN_OPTIONS): OpenMPI's runtime leaks by design
  # (its plugins are unloaded before exit, so LeakSanitizer cannot even name them). The ranks run
  # without leak detection; every other sanitizer check stays on.
  [[ -z ${ASAN_OPTIONS:-} ]] || export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
  "${MPI_PREFIX[@]}" mpirun -n "$k" "$@" >"$log" 2>&1 && return 0
  local status=$? dead r h sig
  # A rank killed outright: mpirun names its rank and node.
  dead=$(sed -nE 's/.*process rank ([0-9]+) with PID [0-9]+ on node ([^ ]+) exited on signal ([0-9]+).*/\1 \2 \3/p' "$log" | head -1)
  if [[ -n $dead ]]; then
    read -r r h sig <<<"$dead"
    MPI_FAILURE="MPI rank $r on $h ($("$describe" "$r")) was killed by signal $sig ($(kill -l "$sig" 2>/dev/null))"
  else
    MPI_FAILURE="mpirun exited with status $status: $(tail -n 5 "$log")"
  fi
  return 1
}
