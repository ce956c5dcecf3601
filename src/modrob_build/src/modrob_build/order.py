"""Module orders: parsing from text and validation against the module database.

Positions in messages are 1-based ("position 3" is the third module of the order).
"""
from modrob_build.errors import OrderError


def parse_order(value):
    """A module order from '59,3,55', '[59, 3, 55]', '59 3 55' or a list of ints/strings.

    Raises OrderError naming the position of a token that is not an integer."""
    if isinstance(value, str):
        text = value.strip().strip("[]")
        tokens = [t for t in text.replace(",", " ").split()]
    elif isinstance(value, (list, tuple)):
        tokens = list(value)
    else:
        raise OrderError("a module order must be a list of module IDs or a string like "
                         "'59,3,55,63,57,5', not %r" % (value,))
    order = []
    for pos, tok in enumerate(tokens, start=1):
        if isinstance(tok, bool):
            raise OrderError("position %d: %r is not a module ID (an integer)" % (pos, tok))
        if isinstance(tok, int):
            order.append(tok)
            continue
        if isinstance(tok, float) and tok.is_integer():
            order.append(int(tok))
            continue
        try:
            order.append(int(str(tok).strip()))
        except ValueError:
            raise OrderError("position %d: '%s' is not a module ID (an integer such as 59)"
                             % (pos, tok))
    return order


def validate_order(order, db):
    """Check an order against the database; returns the list of Module objects.

    Rules: not empty; every ID known; exactly one base, at position 1; at least one joint."""
    shown = "[%s]" % ", ".join(str(i) for i in order)
    if not order:
        raise OrderError("the module order is empty: give the base module first, e.g. "
                         "59,3,55,63,57,5")
    modules = []
    for pos, module_id in enumerate(order, start=1):
        if module_id not in db:
            raise OrderError("order %s, position %d: ID %d is not in the module database %s "
                             "(known IDs: %s)" % (shown, pos, module_id, db.path,
                                                  ", ".join(str(i) for i in db.ids())))
        modules.append(db[module_id])
    bases = ", ".join(str(i) for i in db.base_ids())
    if modules[0].kind != "base":
        raise OrderError("order %s, position 1: ID %d is a %s module, but an order must start "
                         "with a base module (%s)" % (shown, order[0], modules[0].kind, bases))
    for pos, m in enumerate(modules[1:], start=2):
        if m.kind == "base":
            raise OrderError("order %s, position %d: ID %d is a second base module; a robot has "
                             "exactly one base, at position 1" % (shown, pos, m.id))
    if not any(m.is_joint for m in modules):
        raise OrderError("order %s: no joint module (IDs %s); a robot needs at least one joint"
                         % (shown, ", ".join(str(i) for i in db.ids() if db[i].is_joint)))
    return modules
