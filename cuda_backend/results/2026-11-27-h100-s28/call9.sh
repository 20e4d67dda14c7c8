#!/usr/bin/env bash
# Session 28 call 9 (run inline on call 8's machine): the conformance suite on CUDA again with more
# time (call 8's ran past its 100 s limit).
python3 -c "import tarfile; tarfile.open('.devrun/bundle.tar.xz').extractall('.devrun')"; for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig; export LD_LIBRARY_PATH=$PWD/.devrun/lib; cat .devrun/COMMIT
time timeout 200 .devrun/expanse_conformance --backend cuda > $OUT/call9-conformance.log 2>&1; echo "conformance rc $?"; tail -2 $OUT/call9-conformance.log
