#!/bin/sh
# t930_inputs.sh: placeholder until its checks are written
echo "0 passed, 0 failed"
