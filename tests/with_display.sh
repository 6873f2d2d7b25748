#!/usr/bin/env bash
# Runs a command with an X display: the one already there (the README's test command runs the whole
# suite under one xvfb-run), else a virtual one of its own. Starting a second Xvfb inside the first
# for every test raced on display numbers ("bad X server connection") once in a few CI runs.
# -noreset: an X server resets when its last client leaves and refuses connections that arrive
# during the reset (7 % of immediate reconnects under Xvfb, app/x_display.h); the tests' processes
# follow each other closely.
if [ -n "${DISPLAY:-}" ]; then exec "$@"; fi
exec xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" "$@"
