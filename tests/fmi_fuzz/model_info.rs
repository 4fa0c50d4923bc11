//! The variables an importer learns from modelDescription.xml: value reference, type, causality
//! and range (read with a few string searches: the files are this project's own).

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
    pub guid: String,
    pub vars: Vec<Var>,
}

fn attribute(text: &str, name: &str) -> Option<String> {
    let key = format!(" {name}=\"");
    let start = text.find(&key)? + key.len();
    Some(text[start..start + text[start..].find('"')?].to_string())
}

impl ModelInfo {
    pub fn read(path: &str) -> ModelInfo {
        let xml = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
        let guid = attribute(&xml, "guid").expect("guid");
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
                let number = |n: &str| attribute(chunk, n).map(|s| s.parse::<f64>().expect("a number"));
                Var {
                    name: attribute(chunk, "name").expect("name"),
                    vr: attribute(chunk, "valueReference").expect("vr").parse().expect("u32"),
                    ty,
                    causality: attribute(chunk, "causality").unwrap_or_else(|| "local".into()),
                    min: number("min"),
                    max: number("max"),
                }
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
}
