# private_config.sh — sourced by the bench and check scripts that run `pcnc run`: a copy of a
# machine config with its own shared-memory segment, socket and state directory (so a pcnc
# running elsewhere on this machine is not disturbed) and heartbeat timeouts of 2 s instead of
# 0.1 s (on a busy machine a starved process would end a run as "pcnc-rt lost"; they change no
# figure of a run that completes).
# Usage: private_config CONFIG NAME DIR >OUT.toml  (segment /pcnc-NAME-PID, socket and state in DIR)
private_config() {
  sed -e "s#^shm_name = .*#shm_name = \"/pcnc-$2-$$\"#" -e "s#^\# socket_path = .*#socket_path = \"$3/s.sock\"#" \
      -e "s#^\# state_dir = .*#state_dir = \"$3/state\"#" \
      -e "s#^host_timeout_s = .*#host_timeout_s = 2.0#" -e "s#^rt_timeout_s = .*#rt_timeout_s = 2.0#" \
      "$1"
}
