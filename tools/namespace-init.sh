# The init of yadew's PID namespace (run by unshare as PID 1, with the mount namespace private):
#   namespace-init.sh ROOT N DIR_1 ... DIR_N M OPT_1 ... OPT_M CWD CMD...
# binds DIR_1..DIR_N at the same paths inside ROOT, and OPT_1..OPT_M with what is mounted below
# them where the kernel allows (the host's other top-level directories: a failure is ignored),
# mounts /proc, /dev and /dev/shm, and runs CMD
# chrooted into ROOT in CWD as its child.  It forwards TERM and HUP to CMD and turns USR1 into a
# SIGINT for it: an init ignores every signal it has no handler for, so CMD must not be the init
# itself, and SIGINT cannot be forwarded as such because a background command of a shell starts
# with SIGINT ignored (CMD gets the default SIGINT action back through env, or Python would never
# raise KeyboardInterrupt).  When this init ends, the kernel ends everything else in the namespace.
set -e
R=$1; shift; n=$1; shift
mount -t proc proc "$R/proc"; mount --rbind /dev "$R/dev"; mount -t tmpfs tmpfs "$R/dev/shm"
i=0; while [ $i -lt "$n" ]; do d=$1; shift; mkdir -p "$R$d"; mount --bind "$d" "$R$d"; i=$((i+1)); done
m=$1; shift
i=0; while [ $i -lt "$m" ]; do d=$1; shift; { mkdir -p "$R$d" && mount --rbind "$d" "$R$d"; } 2>/dev/null || :; i=$((i+1)); done
cwd=$1; shift
set +e
trap 'kill -TERM $child 2>/dev/null' TERM
trap 'kill -HUP $child 2>/dev/null' HUP
trap 'kill -INT $child 2>/dev/null' USR1
# the terminal stays CMD's input: a background command's input is /dev/null before its own
# redirections, so the original input is passed on through fd 3
exec 3<&0
chroot "$R" /usr/bin/env --default-signal=INT,QUIT /bin/sh -c 'cd "$0" 2>/dev/null || cd /; exec "$@"' "$cwd" "$@" <&3 3<&- &
exec 3<&-
child=$!
rc=0
while kill -0 $child 2>/dev/null; do wait $child; rc=$?; done
exit $rc
