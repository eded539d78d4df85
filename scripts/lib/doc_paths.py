"""What a report writes for a path: the Python twin of doc-paths.sh."""
import re


def doc_paths(text):
    """A path into a build folder of any clone (/tmp/x/build/default) becomes build/default: a report
    names the build by its preset, never a folder of the machine that ran it."""
    return re.sub(r"(^|[\s=`(])(?:/|\.\./)[^\s`)]*/(build/)", r"\1\2", text)
