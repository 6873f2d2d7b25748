#!/usr/bin/env bash
# Runs a command with an X display: the one already there (the README's test command runs the whole
# suite under one xvfb-run), else a virtual one of its own. Starting a second Xvfb inside the first
# for every test raced on display numbers ("bad X server connection") once in a few CI runs.
if [ -n "${DISPLAY:-}" ]; then exec "$@"; fi
exec xvfb-run -a "$@"
