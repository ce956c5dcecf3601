"""The reconfigure window: a filter box and the tree of servers on the left (check a server to
edit it), one panel per checked server on the right, a status line for messages."""
from PyQt5 import QtCore, QtWidgets

from rqt_reconfigure.editors import make_editor
from rqt_reconfigure.errors import ReconfigureError
from rqt_reconfigure.param_model import matches, server_tree

SERVER_ROLE = QtCore.Qt.UserRole + 1


class _Bridge(QtCore.QObject):
    """Carries callbacks from ROS threads into the GUI thread."""
    description = QtCore.pyqtSignal(str, object)
    config = QtCore.pyqtSignal(str, object)
    error = QtCore.pyqtSignal(str)


class ServerPanel(QtWidgets.QGroupBox):
    """Editors for one server, built from its description when it arrives."""

    def __init__(self, name, send, report, parent=None):
        QtWidgets.QGroupBox.__init__(self, name, parent)
        self.setObjectName("panel_" + name)
        self.name = name
        self.send = send
        self.report = report
        self.editors = {}
        self.layout_ = QtWidgets.QVBoxLayout(self)
        self.waiting = QtWidgets.QLabel("waiting for the server's description ...")
        self.layout_.addWidget(self.waiting)
        self._last_config = None

    def build(self, group):
        self.waiting.hide()
        self._add_group(group, self.layout_, top=True)
        if self._last_config is not None:
            self.show_config(self._last_config)

    def _add_group(self, group, layout, top=False):
        box = self if top else QtWidgets.QGroupBox(group.name)
        grid = QtWidgets.QGridLayout()
        grid.setColumnStretch(2, 1)
        for row, spec in enumerate(group.params):
            self.editors[spec.name] = make_editor(spec, grid, row, lambda n, v: self.send(self.name, {n: v}),
                                                  self.report)
        if top:
            layout.addLayout(grid)
        else:
            inner = QtWidgets.QVBoxLayout(box)
            inner.addLayout(grid)
            layout.addWidget(box)
            layout = inner
        for child in group.groups:
            self._add_group(child, layout)

    def show_config(self, config):
        self._last_config = config
        for name, editor in self.editors.items():
            if name in config:
                editor.show(config[name])


class ReconfigureWindow(QtWidgets.QWidget):
    """``connect(name, on_description, on_config, on_error)`` returns a connection with ``set``
    and ``close`` (ServerConnection in use, a fake in tests); ``lister()`` returns server names."""

    def __init__(self, lister, connect, refresh_period=3.0, parent=None):
        QtWidgets.QWidget.__init__(self, parent)
        self.setWindowTitle("Dynamic Reconfigure")
        self.lister = lister
        self.connect_server = connect
        self.connections = {}
        self.panels = {}
        self.servers = []
        self.bridge = _Bridge()
        self.bridge.description.connect(self._on_description)
        self.bridge.config.connect(self._on_config)
        self.bridge.error.connect(self.report)

        self.filter = QtWidgets.QLineEdit()
        self.filter.setObjectName("filter")
        self.filter.setPlaceholderText("Filter key")
        self.filter.textChanged.connect(self._apply_filter)
        self.tree = QtWidgets.QTreeWidget()
        self.tree.setHeaderHidden(True)
        self.tree.itemChanged.connect(self._item_changed)
        self.tree.itemClicked.connect(self._item_clicked)
        refresh = QtWidgets.QPushButton("Refresh")
        refresh.clicked.connect(self.refresh)
        expand = QtWidgets.QPushButton("Expand all")
        expand.clicked.connect(self.tree.expandAll)
        collapse = QtWidgets.QPushButton("Collapse all")
        collapse.clicked.connect(self.tree.collapseAll)
        left = QtWidgets.QWidget()
        lv = QtWidgets.QVBoxLayout(left)
        lv.setContentsMargins(0, 0, 0, 0)
        lv.addWidget(self.filter)
        buttons = QtWidgets.QHBoxLayout()
        buttons.addWidget(collapse)
        buttons.addWidget(expand)
        lv.addLayout(buttons)
        lv.addWidget(self.tree)
        lv.addWidget(refresh)

        self.panel_area = QtWidgets.QWidget()
        self.panel_layout = QtWidgets.QVBoxLayout(self.panel_area)
        self.panel_layout.addStretch(1)
        scroll = QtWidgets.QScrollArea()
        scroll.setWidgetResizable(True)
        scroll.setWidget(self.panel_area)
        splitter = QtWidgets.QSplitter()
        splitter.addWidget(left)
        splitter.addWidget(scroll)
        splitter.setSizes([260, 640])
        self.status = QtWidgets.QLabel("")
        self.status.setObjectName("status")
        self.status.setWordWrap(True)
        self.status.setSizePolicy(QtWidgets.QSizePolicy.Ignored, QtWidgets.QSizePolicy.Preferred)
        outer = QtWidgets.QVBoxLayout(self)
        outer.addWidget(splitter, 1)
        outer.addWidget(self.status)
        self.resize(960, 600)

        self.timer = QtCore.QTimer(self)
        self.timer.timeout.connect(self.refresh)
        if refresh_period > 0:
            self.timer.start(int(refresh_period * 1000))

    # -- servers -----------------------------------------------------------------------------
    def report(self, text):
        self.status.setText(text)

    def refresh(self):
        try:
            servers = self.lister()
        except ReconfigureError as err:
            self.report(str(err))
            return
        if servers == self.servers:
            return
        self.servers = servers
        for gone in [n for n in self.panels if n not in servers]:
            self.close_server(gone)
            self.report("%s went away" % gone)
        self._rebuild_tree()

    def _rebuild_tree(self):
        self.tree.blockSignals(True)
        self.tree.clear()
        names = set(self.servers)

        def add(parent, prefix, subtree):
            for part in sorted(subtree):
                full = prefix + "/" + part
                item = QtWidgets.QTreeWidgetItem([part])
                if full in names:
                    item.setData(0, SERVER_ROLE, full)
                    item.setFlags(item.flags() | QtCore.Qt.ItemIsUserCheckable)
                    item.setCheckState(0, QtCore.Qt.Checked if full in self.panels else QtCore.Qt.Unchecked)
                    item.setToolTip(0, full)
                if parent is None:
                    self.tree.addTopLevelItem(item)
                else:
                    parent.addChild(item)
                add(item, full, subtree[part])

        add(None, "", server_tree(self.servers))
        self.tree.expandAll()
        self.tree.blockSignals(False)
        self._apply_filter(self.filter.text())

    def server_items(self):
        out = {}
        it = QtWidgets.QTreeWidgetItemIterator(self.tree)
        while it.value():
            name = it.value().data(0, SERVER_ROLE)
            if name:
                out[name] = it.value()
            it += 1
        return out

    def _apply_filter(self, text):
        def visit(item):
            name = item.data(0, SERVER_ROLE)
            visible = bool(name) and matches(name, text)
            for i in range(item.childCount()):
                visible = visit(item.child(i)) or visible
            item.setHidden(not visible)
            return visible
        for i in range(self.tree.topLevelItemCount()):
            visit(self.tree.topLevelItem(i))

    def _item_clicked(self, item, column):
        name = item.data(0, SERVER_ROLE)
        if name and name not in self.panels:
            item.setCheckState(0, QtCore.Qt.Checked)

    def _item_changed(self, item, column):
        name = item.data(0, SERVER_ROLE)
        if not name:
            return
        if item.checkState(0) == QtCore.Qt.Checked:
            self.open_server(name)
        else:
            self.close_server(name)

    def open_server(self, name):
        if name in self.panels:
            return self.panels[name]
        panel = ServerPanel(name, self._send, self.report)
        self.panel_layout.insertWidget(self.panel_layout.count() - 1, panel)
        self.panels[name] = panel
        self.connections[name] = self.connect_server(
            name, lambda group: self.bridge.description.emit(name, group),
            lambda config: self.bridge.config.emit(name, config), self.bridge.error.emit)
        item = self.server_items().get(name)
        if item is not None and item.checkState(0) != QtCore.Qt.Checked:
            self.tree.blockSignals(True)
            item.setCheckState(0, QtCore.Qt.Checked)
            self.tree.blockSignals(False)
        return panel

    def close_server(self, name):
        conn = self.connections.pop(name, None)
        if conn is not None:
            conn.close()
        panel = self.panels.pop(name, None)
        if panel is not None:
            panel.setParent(None)
            panel.deleteLater()

    def _send(self, name, changes):
        conn = self.connections.get(name)
        if conn is not None:
            conn.set(changes)
            self.report("%s: %s" % (name, ", ".join("%s = %s" % kv for kv in sorted(changes.items()))))

    def _on_description(self, name, group):
        panel = self.panels.get(name)
        if panel is not None and not panel.editors:
            panel.build(group)

    def _on_config(self, name, config):
        panel = self.panels.get(name)
        if panel is not None:
            panel.show_config(config)

    def closeEvent(self, event):
        for name in list(self.connections):
            self.close_server(name)
        QtWidgets.QWidget.closeEvent(self, event)
