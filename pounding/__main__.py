from pounding.cli import console

console()
