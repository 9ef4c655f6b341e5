#!/bin/sh
# t910_outdir.sh: placeholder until its checks are written
echo "0 passed, 0 failed"
