"""The ``xacro`` command line (xacro 1.14's options)."""
import argparse
import sys
import traceback
import xml.parsers.expat

from .errors import XacroException, error, message
from .output import to_xml


def parse_args(argv):
    try:
        from rosgraph.names import REMAP, load_mappings
        mappings = load_mappings(argv)
        argv = [a for a in argv if REMAP not in a]
    except ImportError:
        mappings = {a.split(":=", 1)[0]: a.split(":=", 1)[1] for a in argv if ":=" in a}
        argv = [a for a in argv if ":=" not in a]
    p = argparse.ArgumentParser(prog="xacro", usage="xacro [options] <input> [name:=value ...]",
                                description="Expand a xacro file (ROS 1 xacro 1.14 semantics).")
    p.add_argument("input", help="the .xacro file")
    p.add_argument("-o", dest="output", metavar="FILE", help="write output to FILE instead of stdout")
    p.add_argument("--deps", action="store_true", dest="just_deps", help="print file dependencies")
    p.add_argument("--inorder", "-i", action="store_true", dest="in_order",
                   help="processing in read order (the default; can be omitted)")
    p.add_argument("--xacro-ns", action="store_true", dest="xacro_ns",
                   help="accepted for xacro 1.13 command lines; has no effect: xacro 1.14 only "
                        "treats xacro:-prefixed tags as xacro's")
    p.add_argument("--legacy", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("-q", action="store_const", dest="verbosity", const=0,
                   help="quiet operation, suppressing warnings")
    p.add_argument("-v", action="count", dest="verbose", default=0, help="increase verbosity")
    p.add_argument("--verbosity", type=int, metavar="level", dest="verbosity",
                   help="0 quiet, 1 warnings and error locations (default), 2 stack traces, "
                        "3 property definitions and uses at top level, 4 at every level")
    opts = p.parse_args(argv)
    if opts.legacy:
        p.error("--legacy processing was removed in xacro 1.14: drop the option "
                "(prefix every xacro tag with xacro: instead)")
    if opts.in_order:
        message("xacro: in-order processing became default in ROS Melodic. You can drop the option.")
    if opts.verbosity is None:
        opts.verbosity = 1 + opts.verbose
    opts.mappings = mappings
    return opts


def main(argv=None):
    from . import process_file
    opts = parse_args(sys.argv[1:] if argv is None else argv)
    processor = None
    try:
        doc, processor = process_file(opts.input, mappings=opts.mappings, verbosity=opts.verbosity,
                                      return_processor=True)
    except xml.parsers.expat.ExpatError as e:
        error("XML parsing error: %s" % e)
        if opts.verbosity > 0:
            _location(e)
            print("\nCheck that:\n - Your XML is well-formed\n - You have the xacro xmlns "
                  "declaration: xmlns:xacro=\"http://www.ros.org/wiki/xacro\"", file=sys.stderr)
        sys.exit(2)
    except Exception as e:   # every error ends as one message and exit code 2, as xacro does
        error(str(e) or repr(e))
        if opts.verbosity > 0:
            _location(e)
        if opts.verbosity > 1 or not isinstance(e, (XacroException, NameError, TypeError, ValueError,
                                                    KeyError, AttributeError, SyntaxError, OSError)):
            traceback.print_exc()
        sys.exit(2)

    if opts.just_deps:
        print(" ".join(sorted(set(processor.includes))))
        return
    text = to_xml(doc)
    if opts.output:
        import os
        folder = os.path.dirname(opts.output)
        if folder:
            os.makedirs(folder, exist_ok=True)
        with open(opts.output, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text + "\n")


def _location(exc):
    processor = getattr(exc, "processor", None)
    if processor is not None:
        processor.print_location()
