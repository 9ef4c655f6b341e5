#!/bin/sh
# t920_limits.sh: placeholder until its checks are written
echo "0 passed, 0 failed"
