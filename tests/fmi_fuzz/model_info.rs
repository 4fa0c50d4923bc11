//! The variables an importer learns from modelDescription.xml, FMI 2.0's or FMI 3.0's: value
//! reference, type, causality and range (read with a few string searches: the files are this
//! project's own).

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    Real,
    Integer,
    Boolean,
}

#[derive(Clone, Debug)]
pub struct Var {
    pub name: String,
    pub vr: u32,
    pub ty: Type,
    pub causality: String,
    pub min: Option<f64>,
    pub max: Option<f64>,
}

pub struct ModelInfo {
    /// FMI 2.0 `guid`, FMI 3.0 `instantiationToken`.
    pub guid: String,
    pub vars: Vec<Var>,
}

fn attribute(text: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = text.find(&key)? + key.len();
    Some(text[start..start + text[start..].find('"')?].to_string())
}

/// One variable's text: FMI 2.0's `<ScalarVariable …>…</ScalarVariable>` (the type an element
/// inside), or FMI 3.0's `<Float64 …/>` (the type the element).
fn variable(chunk: &str, ty: Type) -> Var {
    let number = |n: &str| attribute(chunk, n).map(|s| s.parse::<f64>().expect("a number"));
    Var {
        name: attribute(chunk, "name").expect("name"),
        vr: attribute(chunk, "valueReference").expect("vr").parse().expect("u32"),
        ty,
        causality: attribute(chunk, "causality").unwrap_or_else(|| "local".into()),
        min: number("min"),
        max: number("max"),
    }
}

impl ModelInfo {
    pub fn read(xml: &str) -> ModelInfo {
        if let Some(guid) = attribute(xml, "guid") {
            let vars = xml
                .split("<ScalarVariable")
                .skip(1)
                .map(|chunk| {
                    let chunk = &chunk[..chunk.find("</ScalarVariable>").expect("closed")];
                    let ty = if chunk.contains("<Real") {
                        Type::Real
                    } else if chunk.contains("<Integer") {
                        Type::Integer
                    } else {
                        Type::Boolean
                    };
                    variable(chunk, ty)
                })
                .collect();
            return ModelInfo { guid, vars };
        }
        let guid = attribute(xml, "instantiationToken").expect("guid or instantiationToken");
        let variables =
            &xml[xml.find("<ModelVariables>").expect("ModelVariables")..xml.find("</ModelVariables>").unwrap()];
        let vars = variables
            .split('<')
            .filter_map(|element| {
                let ty = match element.split_whitespace().next()? {
                    "Float64" => Type::Real,
                    "Int32" => Type::Integer,
                    "Boolean" => Type::Boolean,
                    _ => return None,
                };
                Some(variable(element, ty))
            })
            .collect();
        ModelInfo { guid, vars }
    }

    pub fn of(&self, ty: Type) -> impl Iterator<Item = &Var> {
        self.vars.iter().filter(move |v| v.ty == ty)
    }

    pub fn outputs(&self) -> Vec<u32> {
        self.of(Type::Real).filter(|v| v.causality == "output").map(|v| v.vr).collect()
    }

    /// FMI 3.0's independent variable `time`, if the description has one.
    pub fn independent(&self) -> Option<u32> {
        self.vars.iter().find(|v| v.causality == "independent").map(|v| v.vr)
    }
}
