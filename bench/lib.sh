# Shared by the bench scripts (sourced, not run).

# auto_dt BIN SCENE DIR [--set KEY=VALUE ...]: the step a scene's run takes (its `run.dt`, or
# the step `"auto"` chooses), read from the summary of a one-step run written into DIR
# (removed afterwards).
auto_dt() {
  local bin=$1 scene=$2 dir=$3
  shift 3
  "$bin" run "$scene" --quiet --out "$dir" --force --set prepare.duration=0 --set run.duration=1e-9 \
    --set run.checkpoint_interval=0 "$@" 2> /dev/null | tail -1 \
    | python3 -c "import json,sys; print(json.load(sys.stdin)['dt'])"
  rm -rf "$dir"
}
