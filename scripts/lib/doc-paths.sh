# Sourced by the report scripts. doc_paths (a filter) rewrites a path into a build folder of any
# clone, such as /tmp/x/build/default or ../../other/build/default, as build/default: a report
# names the build by its preset, never by a folder of the machine that ran it (tests/docs checks).
doc_paths() { sed -E 's#(^|[ =`(])(/|\.\./)[^ `)]*/(build/)#\1\3#g'; }
