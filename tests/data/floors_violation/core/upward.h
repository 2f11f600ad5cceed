// A file on the lowest floor that includes the top floor: the floors check must refuse this tree.
#pragma once

#include "cli/commands.h"
