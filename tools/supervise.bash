# How yadew runs every command so that it can be stopped (sourced by yadew and by the tests; needs
# MODE, root or native).
#
# supervise CMD...: run CMD (in the background, with the terminal as its input) and wait for it, so
# that signals reach yadew at once and are passed on; nothing outlives yadew:
#   - CMD runs under `setpriv --pdeathsig KILL`: if yadew itself is killed, CMD is killed, and with
#     it (unshare --kill-child) the whole PID namespace of the root;
#   - SIGTERM / SIGHUP to yadew are forwarded; SIGINT (Ctrl-C, or kill -INT) too, after a short
#     grace period in which the command may already be stopping on the terminal's own SIGINT;
#     `./yadew console` leaves Ctrl-C to the YADE console (it interrupts the running command there);
#   - a command that does not stop within 5 s after a forwarded signal gets SIGTERM, then SIGKILL.
# Returns the command's exit status, or 128 + the signal number when a signal stopped it.
SUPERVISE_CONSOLE=${SUPERVISE_CONSOLE:-0}
supervise() {
  local pid sig='' stopped='' rc=0 stdin
  # the terminal stays the command's input (a background command's input is /dev/null before its
  # own redirections, hence the detour through fd 3)
  exec {stdin}<&0
  setpriv --pdeathsig KILL "$@" <&"$stdin" {stdin}<&- &
  pid=$!
  exec {stdin}<&-
  trap 'sig=INT' INT; trap 'sig=TERM' TERM; trap 'sig=HUP' HUP
  while alive "$pid"; do
    if [ -z "$sig" ]; then
      # short waits, cut short by any trapped signal: a signal that lands before a wait starts
      # would otherwise wait for the command itself to end
      sleep 0.2 & wait $! 2>/dev/null || true
      continue
    fi
    case "$sig" in
      INT) [ "$SUPERVISE_CONSOLE" = 1 ] || { stopped=$sig; wait_for_exit "$pid" 30 || stop_command "$pid" INT; } ;;
      *)   stopped=$sig; stop_command "$pid" "$sig" ;;
    esac
    sig=''
  done
  wait "$pid" || rc=$?
  trap - INT TERM HUP
  [ -n "$stopped" ] && [ "$rc" = 0 ] && rc=$((128 + $(kill -l "$stopped")))
  return "$rc"
}

alive() {  # alive PID: the process exists and is not a zombie
  local s; s=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
  s=${s##*) }; [ "${s%% *}" != Z ]
}
wait_for_exit() {  # wait_for_exit PID TENTHS: 0 if PID ended within TENTHS tenths of a second
  local i; for ((i = 0; i < $2; i++)); do alive "$1" || return 0; sleep 0.1; done; return 1
}
# stop_command PID SIGNAL: deliver SIGNAL to the supervised command, then escalate to TERM and KILL.
# In the root the recipient is the namespace's init (the child of unshare), which passes it on.
stop_command() {
  local pid=$1 s target
  for s in "$2" TERM KILL; do
    target=$pid
    if [ "$MODE" = root ]; then
      target=$(awk '{print $1}' "/proc/$pid/task/$pid/children" 2>/dev/null || true)
      [ -n "$target" ] || return 0
      [ "$s" = INT ] && s=USR1
    fi
    kill -s "$s" "$target" 2>/dev/null || return 0
    wait_for_exit "$pid" 50 && return 0
  done
}

