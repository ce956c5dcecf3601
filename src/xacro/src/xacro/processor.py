"""The expansion of a xacro document (xacro 1.14's semantics), in document order.

Only elements in the ``xacro:`` prefix are xacro's (``<xacro:property>``, ``<xacro:macro>``,
``<xacro:include>``, ``<xacro:if>``, ``<xacro:unless>``, ``<xacro:arg>``, ``<xacro:insert_block>``,
``<xacro:element>``, ``<xacro:attribute>``, ``<xacro:call>``, ``<xacro:NAME>`` calling a macro):
a macro called ``link`` is never confused with a URDF ``<link>``. Every other element, attribute
and text is evaluated (``${...}``, ``$(...)``) and kept.

Scoping: a macro body is evaluated in a new scope whose parent is the *caller's* scope (so a
body sees the caller's properties); ``scope="parent"`` / ``scope="global"`` write a property into
the caller's / the document's scope; an ``<xacro:include ns="n">`` gets its own scope read as
``n.name`` (macros as ``<xacro:n.macro>``).
"""
import glob
import os
import sys
import xml.dom
import xml.dom.minidom

from .errors import XacroException, warning
from .expressions import Evaluator
from .macros import Macro, parse_params
from .scope import NameSpace, Table
from .symbols import global_symbols
from .yaml_data import load_yaml

ELEMENT, TEXT, COMMENT = xml.dom.Node.ELEMENT_NODE, xml.dom.Node.TEXT_NODE, xml.dom.Node.COMMENT_NODE
# The URDF format's own elements: a macro named like one of them is meant to be called only with
# the prefix (no warning when the plain element appears).
URDF_TAGS = frozenset(
    "robot link joint inertial origin mass inertia visual collision geometry box cylinder sphere mesh "
    "material color texture parent child axis calibration dynamics limit mimic safety_controller "
    "transmission type joint actuator hardwareInterface mechanicalReduction gazebo plugin sensor".split())


def as_bool(value, condition):
    """A condition's value as xacro reads it: true/True/false/False, a number, or any Python value."""
    try:
        if isinstance(value, str):
            if value in ("true", "True"):
                return True
            if value in ("false", "False"):
                return False
            return bool(int(value))
        return bool(value)
    except (ValueError, TypeError):
        raise XacroException("Xacro conditional \"%s\" evaluated to \"%s\", which is not a boolean "
                             "expression." % (condition, value)) from None


def is_valid_name(name):
    import keyword
    return isinstance(name, str) and name.isidentifier() and not keyword.iskeyword(name)


def attributes(elt, required, optional, warn=True):
    """Values of required and optional attributes (None when absent); warns on others."""
    values = []
    for name in required:
        if not elt.hasAttribute(name):
            raise XacroException("%s: missing attribute '%s'" % (elt.tagName, name))
        values.append(elt.getAttribute(name))
    values += [elt.getAttribute(n) if elt.hasAttribute(n) else None for n in optional]
    extra = [a for a in elt.attributes.keys() if a not in required + optional and not a.startswith("xmlns:")]
    if extra and warn:
        warning("%s: unknown attribute(s): %s" % (elt.tagName, ", ".join(extra)))
    return values


def first_element(node):
    child = node.firstChild
    while child is not None and child.nodeType != ELEMENT:
        child = child.nextSibling
    return child


def next_element(node):
    sib = node.nextSibling
    while sib is not None and sib.nodeType != ELEMENT:
        sib = sib.nextSibling
    return sib


def replace(node, by=None, content_only=False):
    """Put the nodes of ``by`` (one node or a list; their children when content_only) in place of node."""
    parent = node.parentNode
    for new in ([] if by is None else by if isinstance(by, list) else [by]):
        if content_only:
            child = new.firstChild
            while child is not None:
                following = child.nextSibling
                parent.insertBefore(child, node)
                child = following
        else:
            parent.insertBefore(new, node)
    parent.removeChild(node)


class _Barrier(xml.dom.minidom.Text):
    """A blank text node left after an expanded xacro element: comments in front of the next
    xacro element are dropped only up to here, so expanded content keeps its comments."""


def drop_comments_before(node):
    """Remove the comments directly in front of a xacro element (they describe it)."""
    prev = node.previousSibling
    while prev is not None:
        if prev.nodeType == TEXT and not isinstance(prev, _Barrier) and prev.data.isspace() \
                and prev.data.count("\n") <= 1:
            prev = prev.previousSibling
        if prev is not None and prev.nodeType == COMMENT:
            comment, prev = prev, prev.previousSibling
            node.parentNode.removeChild(comment)
        else:
            break
    if node.nextSibling is not None:
        barrier = _Barrier()
        barrier.data = "\n\n"
        barrier.ownerDocument = node.ownerDocument
        node.parentNode.insertBefore(barrier, node.nextSibling)


def import_namespaces(target, source_attributes, where):
    """Copy the xmlns:* declarations of an included root or macro body onto target."""
    for name, value in source_attributes.items():
        if not name.startswith("xmlns:"):
            continue
        old = target.getAttribute(name) if target.hasAttribute(name) else None
        if old is not None and old != value:
            warning("inconsistent namespace redefinitions for %s:\n old: %s\n new: %s (%s)"
                    % (name, old, value, where))
        elif target.nodeType == ELEMENT:
            target.setAttribute(name, value)


def parse(inp, filename=None):
    """A DOM document from a string, a file object, or (inp None) the file ``filename``."""
    if inp is None:
        try:
            with open(filename) as f:
                return xml.dom.minidom.parse(f)
        except OSError as e:
            raise XacroException("%s: %s" % (e.strerror, filename), exc=None) from e
    if isinstance(inp, str):
        return xml.dom.minidom.parseString(inp)
    if hasattr(inp, "read"):
        return xml.dom.minidom.parse(inp)
    return inp


class _IncludeMissing(XacroException):
    pass


class Processor:
    """One xacro run: arguments, the stack of files and macros being expanded, files read."""

    def __init__(self, args=None, verbosity=1, filename=None):
        self.args = {} if args is None else args
        self.verbosity = verbosity
        self.files = [filename]
        self.macro_stack = []
        self.includes = []
        self.evaluate = Evaluator(self.args, lambda: self.files[-1])
        self.globals = global_symbols(self)
        self._unprefixed_warned = set()

    # ---- what expressions can call ----
    def abs_filename(self, spec):
        """spec relative to the folder of the file being read (absolute specs unchanged)."""
        if os.path.isabs(spec):
            return spec
        current = self.files[-1]
        return os.path.join(os.path.dirname(current) if current else ".", spec)

    def load_yaml(self, spec):
        path = self.abs_filename(spec)
        self.includes.append(path)
        self.files.append(path)
        try:
            return load_yaml(path, self.globals)
        finally:
            self.files.pop()

    def print_location(self, stream=None):
        stream = stream or sys.stderr
        label = "when instantiating macro:"
        for macro in reversed(self.macro_stack):
            where = macro.defined_in[-1][-1] if macro.defined_in and macro.defined_in[-1] else None
            print(label, macro.name, "(%s)" % (where or "???"), file=stream)
            label = "instantiated from:"
        label = "in file:" if self.macro_stack else "when processing file:"
        for f in reversed(self.files):
            print(label, f or "string", file=stream)
            label = "included from:"

    def _log(self, event, table, key, value):
        if self.verbosity > 3 or (self.verbosity > 2 and table.depth() == 1):
            print("%s%s %s: %s (%s)" % (" " * table.depth(), event, key, value, self.files[-1]),
                  file=sys.stderr)

    # ---- the document ----
    def process(self, doc):
        root = doc.documentElement
        target = root.getAttribute("xacro:targetNamespace")
        if target:
            root.removeAttribute("xacro:targetNamespace")
            root.setAttribute("xmlns", target)
        macros = Table()
        symbols = Table(self.globals, evaluate=self.evaluate, log=self._log if self.verbosity > 2 else None)
        self.expand(root, macros, symbols)

    def text(self, text, symbols):
        return self.evaluate(text, symbols)

    def expand(self, node, macros, symbols):
        """Evaluate node's attributes and expand its children, in document order."""
        for name, value in list(node.attributes.items()):
            if name.startswith("xacro:"):
                node.removeAttribute(name)
            elif name != "xmlns:xacro":
                node.setAttribute(name, str(self.text(value, symbols)))
        if node.hasAttribute("xmlns:xacro"):
            node.removeAttribute("xmlns:xacro")

        child = node.firstChild
        eval_comments = False
        while child is not None:
            following = child.nextSibling
            if child.nodeType == ELEMENT:
                eval_comments = False
                if self._element(child, macros, symbols):   # renamed in place: look again
                    continue
            elif child.nodeType == TEXT:
                child.data = str(self.text(child.data, symbols))
                if child.data.strip():
                    eval_comments = False
            elif child.nodeType == COMMENT:
                if "xacro:eval-comments" in child.data:
                    eval_comments = "xacro:eval-comments:off" not in child.data
                    replace(child)
                elif eval_comments:
                    child.data = str(self.text(child.data, symbols))
            child = following

    def _element(self, elt, macros, symbols):
        """Handle one child element; True when it was renamed and must be looked at again."""
        tag = elt.tagName
        if tag == "xacro:insert_block":
            self._insert_block(elt, macros, symbols)
        elif tag == "xacro:include":
            self._include(elt, macros, symbols)
        elif tag == "xacro:property":
            self._property(elt, symbols)
        elif tag == "xacro:macro":
            self._define_macro(elt, macros)
        elif tag == "xacro:arg":
            name, default = attributes(elt, ["name", "default"], [])
            if name not in self.args:
                self.args[name] = str(self.text(default, symbols))
            drop_comments_before(elt)
            replace(elt)
        elif tag == "xacro:element":
            name = self.text(attributes(elt, ["xacro:name"], [], warn=False)[0], symbols)
            if not name:
                raise XacroException("xacro:element: empty name")
            elt.removeAttribute("xacro:name")
            elt.tagName = elt.nodeName = str(name)
            return True
        elif tag == "xacro:attribute":
            name, value = [self.text(v, symbols) for v in attributes(elt, ["name", "value"], [])]
            if not name:
                raise XacroException("xacro:attribute: empty name")
            elt.parentNode.setAttribute(str(name), str(value))
            replace(elt)
        elif tag in ("xacro:if", "xacro:unless"):
            drop_comments_before(elt)
            condition, = attributes(elt, ["value"], [])
            keep = as_bool(self.text(condition, symbols), condition)
            if tag == "xacro:unless":
                keep = not keep
            if keep:
                self.expand(elt, macros, symbols)
                replace(elt, by=elt, content_only=True)
            else:
                replace(elt)
        elif tag.startswith("xacro:"):
            self._call(elt, macros, symbols)
        else:
            if tag in macros and tag not in URDF_TAGS and tag not in self._unprefixed_warned:
                self._unprefixed_warned.add(tag)
                warning("<%s> is kept as an XML element although a macro '%s' is defined: xacro 1.14 (ROS "
                        "Noetic) calls macros only as <xacro:%s>; xacro 1.13 and older also called them "
                        "without the prefix. Write <xacro:%s ...> to call it." % (tag, tag, tag, tag))
            self.expand(elt, macros, symbols)
        return False

    def _insert_block(self, elt, macros, symbols):
        name, = attributes(elt, ["name"], [])
        if "**" + name in symbols:
            block, content_only = symbols["**" + name], True
        elif "*" + name in symbols:
            block, content_only = symbols["*" + name], False
        else:
            raise XacroException("Undefined block \"%s\"" % name)
        block = block.cloneNode(True)
        self.expand(block, macros, symbols)
        replace(elt, by=block, content_only=content_only)

    def _include_files(self, spec, symbols):
        path = self.abs_filename(str(self.text(spec, symbols)))
        if any(c in path for c in "*[?"):
            paths = sorted(glob.glob(path))
            if not paths:
                warning("Include tag's filename spec \"%s\" matched no files." % path)
        else:
            paths = [path]
        self.includes.extend(paths)
        return paths

    def _include(self, elt, macros, symbols):
        spec, ns, optional = attributes(elt, ["filename"], ["ns", "optional"])
        if ns:
            ns = str(self.text(ns, symbols))
            ns_macros = NameSpace()
            macros[ns] = ns_macros
            ns_symbols = NameSpace(parent=symbols)
            symbols[ns] = ns_symbols
        else:
            ns_macros, ns_symbols = macros, symbols
        optional = as_bool(self.text(optional, symbols), optional) if optional else False
        if first_element(elt) is not None:
            warning("Child elements of a <xacro:include> tag are ignored")
        roots = []
        for path in self._include_files(spec, symbols):
            if optional and not os.path.exists(path):
                continue
            self.files.append(path)
            try:
                root = parse(None, path).documentElement
            except XacroException as e:
                self.files.pop()
                raise XacroException("cannot include %s: %s (<xacro:include filename=\"%s\">; "
                                     "optional=\"true\" lets a missing file pass)"
                                     % (path, e.__cause__.strerror, spec)) from None
            self.expand(root, ns_macros, ns_symbols)
            roots.append(root)
            import_namespaces(elt.parentNode, root.attributes, path)
            self.files.pop()
        drop_comments_before(elt)
        replace(elt, by=roots, content_only=True)

    def _property(self, elt, table):
        drop_comments_before(elt)
        name, value, default, remove, scope, lazy = attributes(
            elt, ["name"], ["value", "default", "remove", "scope", "lazy_eval"])
        name = self.text(name, table)
        if not is_valid_name(name):
            raise XacroException("Property names must be valid python identifiers: %s" % name)
        if name.startswith("__"):
            raise XacroException("Property names must not start with double underscore: %s" % name)
        remove = as_bool(self.text(remove, table), remove) if remove else False
        if sum([value is not None, default is not None, remove]) > 1:
            raise XacroException("Property attributes default, value, and remove are mutually "
                                 "exclusive: %s" % name)
        replace(elt)
        if remove:
            if name in table:
                del table[name]
            return
        if default is not None:
            if scope is not None:
                warning("%s: default property value can only be defined on local scope" % name)
            if name in table:
                return
            value = default
        if value is None:       # a block property: its content is inserted by insert_block
            name, value = "**" + name, elt
        lazy = as_bool(self.text(lazy, table), lazy) if lazy else True
        target = table
        if scope == "global":
            target, lazy = table.top(), False
        elif scope == "parent":
            if table.parent is table._root:
                warning("%s: no parent scope at global scope" % name)
                return
            target, lazy = table.parent, False
            if not isinstance(table, NameSpace):   # in a macro: skip include namespaces up to the caller
                while isinstance(target, NameSpace):
                    target = target.parent
        if not lazy and isinstance(value, str):
            value = self.text(value, table)
        target.set(name, value, lazy)

    def _define_macro(self, elt, macros):
        drop_comments_before(elt)
        name, params = attributes(elt, ["name"], ["params"])
        if name == "call":
            raise XacroException("Invalid use of macro name 'call'")
        if "." in name:
            raise XacroException("macro names must not contain '.' (reserved for namespaces): %s" % name)
        if name.startswith("xacro:"):
            warning("macro names must not contain prefix 'xacro:': %s" % name)
            name = name[len("xacro:"):]
        macro = macros[name] if dict.__contains__(macros, name) else Macro(name)
        macro.defined_in.append(list(self.files))
        macro.body = elt
        macro.params, macro.defaults = [], {}
        for param, default in parse_params(params or ""):
            macro.params.append(param)
            if default is not None:
                macro.defaults[param] = default
        macros[name] = macro
        replace(elt)

    def _resolve_macro(self, name, macros, symbols):
        """(macro, its macro table, the symbols its body sees as parent) for a possibly dotted name."""
        if name in macros:
            return macros[name], macros, symbols
        *spaces, short = name.split(".")
        if spaces:
            try:
                for ns in spaces:
                    macros, symbols = macros[ns], symbols[ns]
                return macros[short], macros, symbols
            except (KeyError, TypeError):
                pass
        raise XacroException("unknown macro name: xacro:%s (define it with <xacro:macro name=\"%s\" "
                             "...> or include the file that does, before this call)" % (name, name))

    def _call(self, elt, macros, symbols):
        if elt.tagName == "xacro:call":
            name, = attributes(elt, ["macro"], [], warn=False)
            if not name:
                raise XacroException("xacro:call is missing the 'macro' attribute")
            elt.removeAttribute("macro")
            elt.tagName = elt.nodeName = "xacro:" + str(self.text(name, symbols))
        macro, macros, symbols = self._resolve_macro(elt.tagName[len("xacro:"):], macros, symbols)
        body = macro.body.cloneNode(True)
        self.macro_stack.append(macro)   # popped on success only: an error shows where it was
        scope = Table(symbols)
        pending = list(macro.params)
        for name, value in list(elt.attributes.items()):
            if name not in pending:
                raise XacroException("Invalid parameter \"%s\" (the macro takes: %s)"
                                     % (name, " ".join(macro.params) or "no parameters"), macro=macro)
            pending.remove(name)
            scope.set(name, self.text(value, symbols), lazy=False)
            elt.setAttribute(name, "")   # evaluated once, not again below
        self.expand(elt, macros, symbols)   # the blocks, in the caller's scope
        block = first_element(elt)
        for param in [p for p in pending if p.startswith("*")]:
            if block is None:
                raise XacroException("Not enough blocks", macro=macro)
            pending.remove(param)
            scope[param] = block
            block = next_element(block)
        if block is not None:
            raise XacroException("Unused block \"%s\"" % block.tagName, macro=macro)
        for param in list(pending):
            if param.startswith("*") or param not in macro.defaults:
                continue
            forward, default = macro.defaults[param]
            scope.set(param, self._default(forward, default, symbols, macro), lazy=False)
            pending.remove(param)
        if pending:
            raise XacroException("Undefined parameters [%s]" % ",".join(pending), macro=macro)
        self.expand(body, Table(macros), scope)
        drop_comments_before(elt)
        import_namespaces(elt.parentNode, body.attributes, self.files[-1])
        replace(elt, by=body, content_only=True)
        self.macro_stack.pop()

    def _default(self, forward, default, symbols, macro):
        if forward is not None:
            if forward in symbols:
                return symbols[forward]
            if default is None:
                raise XacroException("Undefined property to forward: %s" % forward, macro=macro)
        return self.text(default, symbols)
