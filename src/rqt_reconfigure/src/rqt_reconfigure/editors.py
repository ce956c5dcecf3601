"""Qt editors for one parameter each, laid out in a grid row as rqt_reconfigure shows them:
``name | min | slider | max | value`` for numbers, a check box for bools, a combo box for enums,
a line edit for strings. ``show(value)`` follows the server without sending anything back;
user edits call ``send(name, value)``."""
from PyQt5 import QtCore, QtWidgets

from rqt_reconfigure.errors import ReconfigureError
from rqt_reconfigure.param_model import format_value


class Editor(object):
    """Base: a name label with the description as tool tip."""

    def __init__(self, spec, grid, row, send, report):
        self.spec = spec
        self.send = send
        self.report = report            # report(text): one-line message to the user
        self.label = QtWidgets.QLabel(spec.name)
        self.label.setToolTip(spec.description)
        grid.addWidget(self.label, row, 0)

    def show(self, value):
        raise NotImplementedError


class NumberEditor(Editor):
    """int and double: a slider when the range is finite, always a text field."""

    def __init__(self, spec, grid, row, send, report):
        Editor.__init__(self, spec, grid, row, send, report)
        self.slider = None
        if spec.has_range:
            grid.addWidget(QtWidgets.QLabel(format_value(spec.minimum)), row, 1)
            self.slider = QtWidgets.QSlider(QtCore.Qt.Horizontal)
            self.slider.setObjectName("slider_" + spec.name)
            lo, hi = spec.tick_range()
            self.slider.setRange(lo, hi)
            self.slider.setMinimumWidth(160)
            self.slider.valueChanged.connect(self._slider_moved)
            self.slider.sliderReleased.connect(self._slider_released)
            grid.addWidget(self.slider, row, 2)
            grid.addWidget(QtWidgets.QLabel(format_value(spec.maximum)), row, 3)
        self.edit = QtWidgets.QLineEdit()
        self.edit.setObjectName("edit_" + spec.name)
        self.edit.setMaximumWidth(110)
        self.edit.editingFinished.connect(self._typed)
        grid.addWidget(self.edit, row, 4)
        self._value = None

    def show(self, value):
        self._value = value
        self.edit.setText(format_value(value))
        if self.slider is not None and not self.slider.isSliderDown():
            self.slider.blockSignals(True)
            self.slider.setValue(self.spec.to_ticks(value))
            self.slider.blockSignals(False)

    def _slider_moved(self, ticks):
        value = self.spec.from_ticks(ticks)
        self.edit.setText(format_value(value))
        if not self.slider.isSliderDown():      # keyboard, wheel, click on the groove, setValue()
            self._commit(value)

    def _slider_released(self):
        self._commit(self.spec.from_ticks(self.slider.value()))

    def _typed(self):
        try:
            value = self.spec.parse(self.edit.text())
        except ReconfigureError as err:
            self.report(str(err))
            if self._value is not None:
                self.edit.setText(format_value(self._value))
            return
        if self.slider is not None:
            self.slider.blockSignals(True)
            self.slider.setValue(self.spec.to_ticks(value))
            self.slider.blockSignals(False)
        self._commit(value)

    def _commit(self, value):
        if value != self._value:
            self._value = value
            self.send(self.spec.name, value)


class BoolEditor(Editor):
    def __init__(self, spec, grid, row, send, report):
        Editor.__init__(self, spec, grid, row, send, report)
        self.box = QtWidgets.QCheckBox()
        self.box.setObjectName("check_" + spec.name)
        self.box.toggled.connect(lambda on: self.send(self.spec.name, bool(on)))
        grid.addWidget(self.box, row, 1)

    def show(self, value):
        self.box.blockSignals(True)
        self.box.setChecked(bool(value))
        self.box.blockSignals(False)


class EnumEditor(Editor):
    def __init__(self, spec, grid, row, send, report):
        Editor.__init__(self, spec, grid, row, send, report)
        self.combo = QtWidgets.QComboBox()
        self.combo.setObjectName("enum_" + spec.name)
        for choice in spec.enum:
            self.combo.addItem("%s (%s)" % (choice.name, format_value(choice.value)), choice.value)
            if choice.description:
                self.combo.setItemData(self.combo.count() - 1, choice.description, QtCore.Qt.ToolTipRole)
        self.combo.currentIndexChanged.connect(self._chosen)
        grid.addWidget(self.combo, row, 1, 1, 4)

    def show(self, value):
        index = self.combo.findData(value)
        self.combo.blockSignals(True)
        if index < 0:
            self.combo.addItem("(%s)" % format_value(value), value)
            index = self.combo.count() - 1
        self.combo.setCurrentIndex(index)
        self.combo.blockSignals(False)

    def _chosen(self, index):
        self.send(self.spec.name, self.combo.itemData(index))


class StringEditor(Editor):
    def __init__(self, spec, grid, row, send, report):
        Editor.__init__(self, spec, grid, row, send, report)
        self.edit = QtWidgets.QLineEdit()
        self.edit.setObjectName("edit_" + spec.name)
        self.edit.editingFinished.connect(lambda: self.send(self.spec.name, self.edit.text()))
        grid.addWidget(self.edit, row, 1, 1, 4)

    def show(self, value):
        self.edit.setText(str(value))


def make_editor(spec, grid, row, send, report):
    if spec.enum:
        return EnumEditor(spec, grid, row, send, report)
    if spec.kind == "bool":
        return BoolEditor(spec, grid, row, send, report)
    if spec.kind == "str":
        return StringEditor(spec, grid, row, send, report)
    return NumberEditor(spec, grid, row, send, report)
