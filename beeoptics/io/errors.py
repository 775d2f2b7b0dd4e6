"""The one error type for bad input: it names the file and the field."""


class InputError(ValueError):
    """Input that cannot be used, with the file and the field at fault.

    Parameters
    ----------
    path : str or Path
        The file.
    field : str
        The field, key or column within it; "" for the file as a whole.
    message : str
        What is wrong, and where possible what would be right.
    """

    def __init__(self, path, field, message):
        self.path = str(path)
        self.field = field
        where = f"{self.path}: {field}" if field else self.path
        super().__init__(f"{where}: {message}")
